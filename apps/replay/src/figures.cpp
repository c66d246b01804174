// A replay's figures as tidy rows (flipper/record/figures.hpp): everything report.md shows and
// the plots draw, from the metrics of one variant. Metric names are documented in
// docs/experiments.md §3.
#include "flipper/replay/figures.hpp"

#include <cstdio>

namespace flipper::replay {
namespace {

class Rows {
 public:
  Rows(std::string variant, std::vector<record::Figure>& out)
      : variant_(std::move(variant)), out_(out) {}
  void add(const std::string& source, const std::string& group, const std::string& metric,
           double value, const std::string& unit = "", bool timing = false) {
    out_.push_back({variant_, source, group, metric, value, unit, timing});
  }
  void summary(const std::string& source, const std::string& group, const std::string& metric,
               const Summary& s, const std::string& unit) {
    add(source, group, metric + "_mean", s.mean, unit);
    add(source, group, metric + "_min", s.min, unit);
    add(source, group, metric + "_max", s.max, unit);
  }

 private:
  std::string variant_;
  std::vector<record::Figure>& out_;
};

// The paper's whole-study figures (both studies, every run), for reference.
struct PaperTokens {
  const char* group;
  double successful, all;
};
constexpr PaperTokens kPaperTokens[] = {{"A", 1150, 1586}, {"B", 585, 831}, {"C", 487, 670}};

void side_figures(Rows& r, const std::string& source, const Figures& f) {
  for (const auto& [g, s] : f.tokens_all) r.add(source, g, "participants", s.n, "participants");
  for (const auto& [g, s] : f.tokens_successful)
    r.summary(source, g, "tokens_successful", s, "tokens");
  for (const auto& [g, s] : f.tokens_all) r.summary(source, g, "tokens_all", s, "tokens");
  for (const auto& [g, n] : f.tokens_successful_sum)
    r.add(source, g, "tokens_successful_sum", n, "tokens");
  for (const auto& [g, s] : f.induced) r.summary(source, g, "induced", s, "commands");
  for (const auto& [g, s] : f.core) r.summary(source, g, "core", s, "commands");
  if (f.others.n > 0) {
    r.summary(source, "C", "by_others", f.others, "commands");
    r.summary(source, "C", "by_self", f.self, "commands");
  }
}

void agreement_figures(Rows& r, const std::string& group, const Agreement& a) {
  r.add("ours", group, "queries", a.n, "queries");
  r.add("ours", group, "agree", a.agree, "queries");
  r.add("ours", group, "agreement", a.n ? 100.0 * a.agree / a.n : 0.0, "%");
}

std::string bin_label(double edge) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", edge);
  return b;
}

}  // namespace

std::vector<record::Figure> replay_figures(const std::string& variant, const Metrics& m) {
  std::vector<record::Figure> out;
  Rows r(variant, out);
  side_figures(r, "ours", m.ours);
  side_figures(r, "original", m.original);
  for (const auto& p : kPaperTokens) {
    r.add("paper", p.group, "tokens_successful_mean", p.successful, "tokens");
    r.add("paper", p.group, "tokens_all_mean", p.all, "tokens");
  }
  r.add("paper", "B", "induced_mean", 54.6, "commands");
  r.add("paper", "B", "core_mean", 72.9, "commands");
  r.add("paper", "C", "induced_mean", 51.8, "commands");
  r.add("paper", "C", "core_mean", 54.3, "commands");
  r.add("paper", "C", "by_others_mean", 37.2, "commands");
  r.add("paper", "C", "by_self_mean", 14.6, "commands");

  agreement_figures(r, "all", m.overall);
  for (const auto& [g, a] : m.by_group) agreement_figures(r, g, a);
  for (const char* original : {"Core", "Induced", "Nothing"}) {
    int total = 0;
    auto row = m.overall.confusion.find(original);
    for (const char* ours : {"core", "induced", "unparsable", "error"}) {
      int n = 0;
      if (row != m.overall.confusion.end())
        if (auto it = row->second.find(ours); it != row->second.end()) n = it->second;
      total += n;
      r.add("ours", std::string(original) + "->" + ours, "confusion", n, "queries");
    }
    r.add("ours", original, "original_status", total, "queries");
  }
  r.add("ours", "all", "floating_tops", m.floating, "queries");
  for (const auto& [g, n] : m.floating_by_group) r.add("ours", g, "floating_tops", n, "queries");

  const auto& e = m.exec;
  r.add("ours", "all", "accepts", e.accepts, "accepts");
  r.add("ours", "all", "accepts_matched", e.matched, "accepts");
  r.add("ours", "all", "accepts_executed", e.executed, "accepts");
  r.add("ours", "all", "accepts_compared", e.compared, "accepts");
  r.add("ours", "all", "exec_robot_agree", e.robot, "accepts");
  r.add("ours", "all", "exec_held_agree", e.held, "accepts");
  r.add("ours", "all", "exec_floor_agree", e.floor, "accepts");
  r.add("ours", "all", "exec_all_agree", e.all, "accepts");
  r.add("ours", "all", "accepts_classified", e.classified, "accepts");
  r.add("ours", "all", "unexplained", e.unexplained, "accepts");
  for (const auto& [cls, n] : e.classes) r.add("ours", cls, "accept_class", n, "accepts");
  for (const auto& [note, n] : e.not_executed) r.add("ours", note, "not_executed", n, "accepts");
  r.add("ours", "all", "accepted_first", m.accepted_top1, "accepts");
  r.add("ours", "all", "accepted_top3", m.accepted_top3, "accepts");

  const PlannerFigures& p = m.planner;
  r.add("ours", "all", "plan_runs", p.runs, "accepts");
  r.add("ours", "all", "plan_success", p.success, "accepts");
  r.add("ours", "all", "plan_success_rate", p.runs ? 100.0 * p.success / p.runs : 0.0, "%");
  r.add("ours", "all", "path_length_sum", static_cast<double>(p.path_length), "cells");
  r.add("ours", "all", "path_length_mean",
        p.executed ? static_cast<double>(p.path_length) / p.executed : 0.0, "cells");
  r.add("ours", "all", "turns_sum", static_cast<double>(p.turns), "turns");
  r.add("ours", "all", "turns_mean", p.executed ? static_cast<double>(p.turns) / p.executed : 0.0,
        "turns");
  r.add("ours", "all", "plan_calls", static_cast<double>(p.plan_calls), "calls");
  r.add("ours", "all", "plan_cpu_sum", p.plan_cpu_ms, "ms", true);
  r.add("ours", "all", "plan_cpu_p50", p.plan_cpu_ms_p50, "ms", true);
  r.add("ours", "all", "plan_cpu_p90", p.plan_cpu_ms_p90, "ms", true);

  // Latency: ours is measured (timing); the original's is the study's log (a fixed figure).
  for (const auto& [source, l, timing] :
       {std::tuple<const char*, const Latency*, bool>{"ours", &m.our_latency, true},
        {"original", &m.original_latency, false}}) {
    r.add(source, "all", "latency_n", l->summary.n, "queries");
    r.add(source, "all", "latency_p50", l->p50, "ms", timing);
    r.add(source, "all", "latency_p90", l->p90, "ms", timing);
    r.add(source, "all", "latency_p99", l->p99, "ms", timing);
    r.add(source, "all", "latency_max", l->summary.max, "ms", timing);
    const auto& edges = latency_bins();
    for (std::size_t i = 0; i + 1 < edges.size(); ++i)
      r.add(source, bin_label(edges[i]), "latency_histogram", l->histogram[i], "queries", timing);
  }

  r.add("ours", "all", "preloaded", m.preloaded, "definitions");
  r.add("ours", "all", "preloaded_ok", m.preloaded_ok, "definitions");
  r.add("ours", "all", "defines", m.defines, "definitions");
  r.add("ours", "all", "defines_ok", m.defines_ok, "definitions");
  for (const auto& [code, n] : m.define_errors)
    r.add("ours", code, "define_errors", n, "definitions");
  int compared = 0;
  for (const auto& [match, n] : m.rule_match) {
    r.add("ours", match, "rule_match", n, "definitions");
    compared += n;
  }
  r.add("ours", "all", "rule_match_compared", compared, "definitions");
  int identity_compared = 0;
  for (const auto& [cls, n] : m.rule_identity) {
    r.add("ours", cls, "rule_identity", n, "definitions");
    identity_compared += n;
  }
  r.add("ours", "all", "rule_identity_compared", identity_compared, "definitions");
  r.add("ours", "all", "rule_action_hole", m.rule_action_hole, "definitions");
  r.add("ours", "all", "deletes", m.deletes, "deletions");
  r.add("ours", "all", "deletes_mapped", m.deletes_mapped, "deletions");
  r.add("ours", "all", "rules_deleted", m.rules_deleted, "rules");
  return out;
}

}  // namespace flipper::replay
