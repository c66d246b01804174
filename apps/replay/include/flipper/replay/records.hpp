#pragma once
/// @file records.hpp
/// What a replay produces: one plain row per replayed command. The metrics are computed from
/// these rows only, so they can be checked exactly on hand-made rows.

#include <string>
#include <vector>

namespace flipper::replay {

/// A `:q` and our answer to it.
struct QueryRow {
  std::string qid, run, group, user, phase, utterance;
  bool in_authors_tables = false;
  int tokens = 0;               ///< sdk::tokenize(utterance).size()
  std::string original;         ///< Core / Induced / Nothing
  std::string ours;             ///< core / induced / unparsable / error
  std::string original_author;  ///< None / Self / Other ("" when not logged)
  std::string our_author;       ///< none / self / other (authors of our top candidate)
  /// Our top candidate's best derivation leaves words out (the `floating` parser); a non-core
  /// top candidate that uses no induced rule has author "none".
  bool floating = false;
  int original_parses = 0;
  int our_candidates = 0;
  double ms = 0;           ///< our query answer's `ms`
  double original_ms = 0;  ///< the original's walltime_s * 1000
  /// With ReplayOptions::repair, for an original "Nothing" we cannot parse either: the repair's
  /// nearest sentences, best first (their token text and canonical formula).
  std::vector<std::string> suggestions, suggestion_formulas;
};

/// A `:accept`: whether we had the accepted program, and what executing it did.
struct AcceptRow {
  std::string qid, run, group, user;
  bool matched = false;   ///< some candidate of ours equals the accepted program
  int rank = -1;          ///< its rank among our candidates
  bool executed = false;  ///< our accept succeeded
  bool compared = false;  ///< the original's next world is known
  bool robot = false, held = false, floor = false;  ///< agreement after executing
  std::string note;                                 ///< why not matched/executed
  /// Why the worlds differ (corpus::class_id of flipper/corpus/accept_diff.hpp; "agree" when
  /// they do not): set when the accepted program was executed or failed and the next world is
  /// known; "" otherwise.
  std::string diff;
  /// The planner on the accepted program, when it was run (matched): whether every primitive
  /// succeeded (executed and realizable); for an executed program the robot's path (moves in
  /// the trace: cells walked) and its turns (a move whose direction differs from the move before
  /// it, picks and drops in between ignored), the planner calls (`plan` and `tour`) the execution
  /// made and their CPU time (thread CPU, ms: a timing figure).
  bool plan_success = false;
  int path_length = 0, turns = 0, plan_calls = 0;
  double plan_cpu_ms = 0;
};

/// A definition (`def`, `def_ret`, `def_iso`, or a preloaded one).
struct DefineRow {
  std::string qid, run, user, head;
  bool preloaded = false;
  bool ok = false;
  std::string error_code;
  int rules = 0;
  /// Our rules against the original's logged ones (rule_oracle.hpp): identical, subset,
  /// overlap, missing; "" when the original logged no comparable rule.
  std::string rule_match;
  /// The rule-identity class (rule_oracle.hpp classify_rules): identical, present, subset,
  /// superset, overlap, disjoint; "" when the original logged no comparable rule.
  std::string rule_identity;
  bool action_hole = false;  ///< the original's rule has an $Action hole, none of ours has
};

/// A `:delete`, mapped to the rules of one definition (see deletion_map.hpp).
struct DeleteRow {
  std::string qid, run, user;
  int rule_index = -1;
  std::string definition;            ///< def_id the index was mapped to ("" if none)
  std::vector<std::string> deleted;  ///< our rule ids deleted
  std::string note;
};

struct ReplayResult {
  std::vector<QueryRow> queries;
  std::vector<AcceptRow> accepts;
  std::vector<DefineRow> defines;
  std::vector<DeleteRow> deletes;
  std::vector<std::string> runs;  ///< replayed runs
};

}  // namespace flipper::replay
