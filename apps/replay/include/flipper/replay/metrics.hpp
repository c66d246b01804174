#pragma once
/// @file metrics.hpp
/// Metrics of one replay, all computed from the rows (records.hpp), so the same code yields the
/// paper's figures from our statuses and from the original's logged ones.
///
/// Figure filter (the authors' tables): `q` commands with phase == "task" of participants with
/// in_authors_tables; per-participant figures average over those participants (the user field,
/// i.e. the merged participant label). Successful = status not Nothing / unparsable / error.
/// Agreement and the confusion matrix cover every replayed `q`.

#include <map>
#include <string>
#include <vector>

#include "flipper/replay/records.hpp"

namespace flipper::replay {

/// Our status in the original's vocabulary: core -> Core, induced -> Induced, else Nothing.
std::string as_original_status(const std::string& ours);
bool figure_row(const QueryRow& r);

/// Counts of one participant over figure rows, for one side (ours or the original's).
struct ParticipantCounts {
  std::string group, user;
  int queries = 0, core = 0, induced = 0, failed = 0;
  int tokens_all = 0, tokens_successful = 0;
  int by_self = 0, by_others = 0;  ///< induced top parse using own / others' rules
  int agree = 0;                   ///< our status equals the original's (same on both sides)
};

struct Summary {
  double mean = 0, min = 0, max = 0;
  int n = 0;
};
Summary summarize(const std::vector<double>& values);

/// The paper's figures for one side.
struct Figures {
  std::map<std::string, Summary> tokens_successful, tokens_all;  ///< by group, per participant
  std::map<std::string, int> tokens_successful_sum, tokens_all_sum;
  std::map<std::string, Summary> induced, core;  ///< groups B and C, per participant
  Summary others, self;                          ///< group C, per participant
  std::vector<ParticipantCounts> participants;   ///< sorted by group, user
};
/// `ours` selects which status/author fields are read.
Figures figures(const std::vector<QueryRow>& rows, bool ours);

struct Agreement {
  int n = 0, agree = 0;
  double rate() const { return n ? static_cast<double>(agree) / n : 0.0; }
  /// original status (Core/Induced/Nothing) -> our status (core/induced/unparsable/error) -> n
  std::map<std::string, std::map<std::string, int>> confusion;
};
Agreement agreement(const std::vector<QueryRow>& rows, const std::string& group = "");

struct ExecAgreement {
  int accepts = 0, matched = 0, executed = 0, compared = 0;
  int robot = 0, held = 0, floor = 0, all = 0;
  /// AcceptRow::diff -> rows (every classified accept: compared, or failed with a known next
  /// world); "agree" counts the same rows as `all`.
  std::map<std::string, int> classes;
  int classified = 0;
  int unexplained = 0;  ///< rows whose class is corpus::is_unexplained
  /// Accepts not executed, by AcceptRow::note (e.g. the accepted formula is not among the
  /// original's logged candidates, so its program is unknown).
  std::map<std::string, int> not_executed;
};
ExecAgreement exec_agreement(const std::vector<AcceptRow>& rows);
/// Whether a class id (AcceptRow::diff) is one nothing in the spec explains (unknown ids too).
bool unexplained_class(const std::string& id);

/// The planner on the accepted programs (AcceptRow's planner figures): `runs` accepts whose
/// program was run (matched), `success` of them executed with every primitive succeeding;
/// path length and turns summed over the executed ones; planner calls and their CPU time.
struct PlannerFigures {
  int runs = 0, executed = 0, success = 0;
  long path_length = 0, turns = 0;
  long plan_calls = 0;
  double plan_cpu_ms = 0;  ///< sum (a timing figure)
  /// Per executed accept whose program called the planner (timing).
  double plan_cpu_ms_p50 = 0, plan_cpu_ms_p90 = 0;
};
PlannerFigures planner_figures(const std::vector<AcceptRow>& rows);

struct Latency {
  Summary summary;
  double p50 = 0, p90 = 0, p99 = 0;
  std::vector<int> histogram;  ///< counts per log bin (latency_bins())
};
/// Log-scale bin edges in ms: 0.01, 0.1-ish steps of x sqrt(10) up to 100 s.
const std::vector<double>& latency_bins();
Latency latency(std::vector<double> ms);

struct Metrics {
  Agreement overall;
  std::map<std::string, Agreement> by_group;
  Figures ours, original;
  ExecAgreement exec;
  PlannerFigures planner;
  Latency our_latency, original_latency;
  int defines = 0, defines_ok = 0, preloaded = 0, preloaded_ok = 0;
  std::map<std::string, int> define_errors;
  /// Definitions (users' and preloaded) by DefineRow::rule_match, compared ones only.
  std::map<std::string, int> rule_match;
  /// Definitions by DefineRow::rule_identity (compared ones only), and how many of the differing
  /// ones miss the original's $Action hole.
  std::map<std::string, int> rule_identity;
  int rule_action_hole = 0;
  int deletes = 0, deletes_mapped = 0, rules_deleted = 0;
  /// Queries whose top reading floats (QueryRow::floating), overall and by group.
  int floating = 0;
  std::map<std::string, int> floating_by_group;
  /// Matched accepts whose program is our first (first three) candidate: the ranking's quality.
  int accepted_top1 = 0, accepted_top3 = 0;
};
Metrics compute_metrics(const ReplayResult& result);

}  // namespace flipper::replay
