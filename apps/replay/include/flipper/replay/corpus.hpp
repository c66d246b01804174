#pragma once
/// @file corpus.hpp
/// The user-study corpus split (data/study2018/README.md): worlds, commands in log order,
/// definitions (also the preloaded expert ones) and, when present, the original server's full
/// answers. Loaded once; the replay and the metrics read it, never change it.

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace flipper::replay {

/// One body line of a definition.
struct BodyLine {
  std::string utterance;
  std::string formula;  ///< the program meant (the original's formula, or canonical text)
  int rank = -1;        ///< a studio line without a formula: the reading chosen (-1: none logged)
  std::string accept_qid = {};  ///< a studio line taught from history: the accept it came from
};

/// One induced rule of the original's grammar log (what the deletion mapping and the rule
/// oracle need).
struct LoggedRule {
  int line = 0;  ///< line in the run's grammar log (identity)
  bool simple_packing = false;
  bool alignment = false;        ///< induced by alignment (`align`)
  std::string lhs;               ///< e.g. "$Action"
  std::vector<std::string> rhs;  ///< tokens and the original's category names
  std::string semantics = {};    ///< studio recordings: the template (canonical text)
};

/// One non-context command of queries.jsonl.
struct Command {
  std::string qid, source, group, session, user, kind, phase, syntax;
  std::optional<std::string> participant;
  bool in_authors_tables = false;
  int line = 0;
  std::string utterance;  ///< empty for dictionary/delete
  std::string world_id, next_world_id;
  // q
  std::string status;  ///< Core / Induced / Nothing
  int n_parses = 0;
  double walltime_s = 0;
  std::optional<std::string> author;  ///< None / Self / Other, when logged
  // accept
  std::string formula, for_qid;
  // def*
  std::string head, def_id;
  std::vector<BodyLine> body;
  // delete
  int rule_index = -1;  ///< the 2018 grammar-log index (-1: none)
  std::string rule;     ///< studio: the live rule id
  int rule_pos = -1;    ///< studio: the rule's index in its define's answer (with def_id)
};

struct Definition {
  std::string def_id, origin, source, group, session, kind, head, rules_status;
  std::optional<std::string> user;
  int line = 0;
  std::vector<BodyLine> body;
  std::vector<LoggedRule> rules;
  /// The author to define it as: user, else the session id.
  std::string author() const { return user ? *user : session; }
};

/// The original's candidate list for one `:q` (original-answers.jsonl).
struct OriginalAnswer {
  struct Candidate {
    std::string pretty, formula;
    bool core_only = false;
    nlohmann::json path;  ///< the original's own run (`result.path`); null when not logged
  };
  std::vector<Candidate> candidates;
  std::optional<int> accepted_rank;
};

/// One server run: its commands in log order and its group.
struct Run {
  std::string source;
  std::string group;                  ///< the most frequent group of its commands (A/B/C)
  std::vector<std::size_t> commands;  ///< indices into Corpus::commands
};

struct Corpus {
  std::string dir;
  std::unordered_map<std::string, nlohmann::json> worlds;  ///< world_id -> protocol world object
  std::vector<Command> commands;                           ///< file order (= log order per run)
  std::vector<Definition> definitions;
  std::unordered_map<std::string, std::size_t> definition_index;  ///< def_id -> index
  std::unordered_map<std::string, OriginalAnswer> answers;        ///< qid -> answer
  std::vector<Run> runs;                                          ///< in order of first command

  const Run* find_run(const std::string& source) const;
  /// The preloaded definitions of a run (origin preloaded or grammar_log_only), in grammar-log
  /// order.
  std::vector<const Definition*> preloaded(const std::string& source) const;
};

/// Loads a corpus directory (worlds.jsonl, queries.jsonl, definitions.jsonl, optional
/// original-answers.jsonl). Throws sdk::Error(bad_corpus) naming the file and line.
Corpus load_corpus(const std::string& dir);

/// The protocol world object of a worlds.jsonl record (walls, items, robot, rooms, bounds).
nlohmann::json protocol_world(const nlohmann::json& record);

inline constexpr const char* kBadCorpus = "bad_corpus";

}  // namespace flipper::replay
