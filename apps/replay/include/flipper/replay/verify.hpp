#pragma once
/// @file verify.hpp
/// `flipper replay verify REC`: a studio study recording replayed exchange by exchange
/// (docs/experiments.md §8, docs/studio.md §7). Per study group one runtime with the group's
/// lexicon mode, a store in memory and the recording's own preload (REC/preload-C.jsonl); per
/// participant's protocol session one kernel Session with the participant's user; each
/// `request` of exchanges.jsonl fed in file order, and our answer compared byte for byte with the
/// recorded one, both without their `ms` members (corpus::answer_for_digest). The recorded
/// answer must also still match its recorded SHA-256. Stops at the first divergence.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace flipper::replay {

struct VerifyOptions {
  std::optional<std::string> config_file;  ///< the server's --config (empty: embedded default)
  std::vector<std::string> sets;           ///< the server's --set overrides
};

struct VerifyResult {
  std::size_t exchanges = 0;  ///< compared (all of them when `equal`)
  bool equal = true;
  std::string divergence;          ///< the first one, with request and both answers
  std::vector<std::string> notes;  ///< e.g. a group config that differs from study.json's
};

/// Throws sdk::Error(bad_corpus) for a folder that is no studio recording (no study.json or
/// exchanges.jsonl, a line that does not read), and sdk::Error for a bad config.
VerifyResult verify_recording(const std::string& dir, const VerifyOptions& options);

}  // namespace flipper::replay
