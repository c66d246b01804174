#pragma once
/// @file replayer.hpp
/// Replays runs of a corpus split through kernel sessions, in log order: one Session per run
/// (fresh in-memory lexicon), the sharing mode from the run's group (A core, B private, C shared
/// with the run's preloaded expert definitions defined first), alignment off as in the study.
///
/// Per command: the world from its `world_id` is set first when it differs from the session's
/// (after an accept the session holds our own world, so the next command resets it to the
/// logged one); the user from its `user` field.
/// - `q`: query; our status, top candidate's authors, and `ms` are recorded.
/// - `accept`: the accepted formula is looked up in the original's answer for `for_qid`
///   (original-answers.jsonl) to get its canonical text, which is read with sdk::read_canonical
///   and compared structurally (sdk::equal) with every candidate of our last query (falling
///   back to comparing rendered text); the matching rank is accepted (re-querying with a larger
///   `k` when it was not among the shown ones) and our world after is compared with the logged
///   `next_world_id` world. No match: counted as absent.
/// - `def`/`def_ret`/`def_iso`: define head + body utterances (top candidate of each line).
/// - `delete`: mapped with DeletionMap, our rules deleted as the deleting user.
/// - `reject`, `dictionary`: nothing to do.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/records.hpp"

namespace flipper::replay {

struct ReplayOptions {
  std::optional<std::string> config_file;  ///< empty: the embedded default
  std::vector<std::string> sets;           ///< overrides applied after the run's mode keys
  std::vector<std::string> runs;           ///< sources to replay (empty: all)
  int max_queries = 0;                     ///< per run: stop before the (N+1)-th `q` (0: all)
  /// Definitions: false, each body line means the program the user accepted for it (its logged
  /// formula, as the 2018 server induced from it; a line without one is parsed); true, every
  /// line is parsed from its text.
  bool reparse_bodies = false;
  /// Queries the original answered with no parse ask for a repair (docs/protocol.md "Repairs");
  /// its nearest sentences go into QueryRow::suggestions (repair_hits.hpp measures them).
  bool repair = false;
  /// Progress: commands done, commands total, the current run.
  std::function<void(std::size_t, std::size_t, const std::string&)> progress;
};

/// The config overrides a run's group implies (lexicon.path, lexicon.sharing, alignment off;
/// alignment_overrides may turn it back on for a run).
std::vector<std::string> mode_overrides(const std::string& group);

/// The alignment a 2018 run ran with, read from its log (docs/naturalization.md §4.8): a run
/// whose logged definitions hold alignment rules (the February 2018 runs) ran with the window
/// alignment of its time: `induction.alignment=true`, `induction.alignment_mode=window`. Any
/// other run (and a studio recording) keeps mode_overrides' alignment off. Applied after
/// mode_overrides, before the caller's keys.
std::vector<std::string> alignment_overrides(const Corpus& corpus, const Run& run);

/// Whose rules a 2018 run's definitions were induced against, read from its log: the 2018
/// server had one grammar, so in its private runs a definition's head parse saw every user's
/// rules (feb2018/groupB1#494, #779, #782 pack another user's; docs/naturalization.md §4.1):
/// `induction.view=everyone` for a run whose logged rules are the 2018 system's (no
/// `semantics` in our notation); none for a studio recording.
std::vector<std::string> view_overrides(const Corpus& corpus, const Run& run);

/// The runs named (all when `names` is empty), in the order given. Throws
/// sdk::Error(bad_request) for an unknown run, listing the corpus's runs.
std::vector<const Run*> select_runs(const Corpus& corpus, const std::vector<std::string>& names);

/// Replays the selected runs. Throws sdk::Error for an unknown run or a bad config.
ReplayResult replay(const Corpus& corpus, const ReplayOptions& options);

}  // namespace flipper::replay
