// Metrics from replay rows (see metrics.hpp for the definitions and the figure filter).
#include "flipper/replay/metrics.hpp"

#include <algorithm>
#include <cmath>

#include "flipper/corpus/accept_diff.hpp"

namespace flipper::replay {

std::string as_original_status(const std::string& ours) {
  if (ours == "core") return "Core";
  if (ours == "induced") return "Induced";
  return "Nothing";
}

bool figure_row(const QueryRow& r) {
  return r.phase == "task" && r.in_authors_tables;
}

Summary summarize(const std::vector<double>& v) {
  Summary s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  s.min = *std::min_element(v.begin(), v.end());
  s.max = *std::max_element(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  return s;
}

Figures figures(const std::vector<QueryRow>& rows, bool ours) {
  std::map<std::pair<std::string, std::string>, ParticipantCounts> by;
  for (const auto& r : rows) {
    if (!figure_row(r)) continue;
    auto& p = by[{r.group, r.user}];
    p.group = r.group;
    p.user = r.user;
    const std::string status = ours ? as_original_status(r.ours) : r.original;
    ++p.queries;
    p.tokens_all += r.tokens;
    if (status != "Nothing") p.tokens_successful += r.tokens;
    (status == "Core" ? p.core : status == "Induced" ? p.induced : p.failed) += 1;
    if (status == "Induced") {
      const std::string author = ours ? r.our_author : r.original_author;
      if (author == "self" || author == "Self") ++p.by_self;
      if (author == "other" || author == "Other") ++p.by_others;
    }
    if (as_original_status(r.ours) == r.original) ++p.agree;
  }
  Figures f;
  std::map<std::string, std::vector<double>> ts, ta, ind, core;
  std::vector<double> others, self;
  for (auto& [key, p] : by) {
    ts[p.group].push_back(p.tokens_successful);
    ta[p.group].push_back(p.tokens_all);
    f.tokens_successful_sum[p.group] += p.tokens_successful;
    f.tokens_all_sum[p.group] += p.tokens_all;
    if (p.group == "B" || p.group == "C") {
      ind[p.group].push_back(p.induced);
      core[p.group].push_back(p.core);
    }
    if (p.group == "C") {
      others.push_back(p.by_others);
      self.push_back(p.by_self);
    }
    f.participants.push_back(p);
  }
  for (auto& [g, v] : ts) f.tokens_successful[g] = summarize(v);
  for (auto& [g, v] : ta) f.tokens_all[g] = summarize(v);
  for (auto& [g, v] : ind) f.induced[g] = summarize(v);
  for (auto& [g, v] : core) f.core[g] = summarize(v);
  f.others = summarize(others);
  f.self = summarize(self);
  return f;
}

Agreement agreement(const std::vector<QueryRow>& rows, const std::string& group) {
  Agreement a;
  for (const auto& r : rows) {
    if (!group.empty() && r.group != group) continue;
    ++a.n;
    if (as_original_status(r.ours) == r.original) ++a.agree;
    ++a.confusion[r.original][r.ours];
  }
  return a;
}

bool unexplained_class(const std::string& id) {
  const auto c = corpus::class_from_id(id);
  return !c || corpus::is_unexplained(*c);  // an unknown id explains nothing
}

ExecAgreement exec_agreement(const std::vector<AcceptRow>& rows) {
  ExecAgreement e;
  for (const auto& r : rows) {
    ++e.accepts;
    e.matched += r.matched;
    e.executed += r.executed;
    if (!r.executed) ++e.not_executed[r.note.empty() ? "unknown" : r.note];
    if (!r.diff.empty()) {
      ++e.classes[r.diff];
      ++e.classified;
      e.unexplained += unexplained_class(r.diff);
    }
    if (!r.compared) continue;
    ++e.compared;
    e.robot += r.robot;
    e.held += r.held;
    e.floor += r.floor;
    e.all += r.robot && r.held && r.floor;
  }
  return e;
}

const std::vector<double>& latency_bins() {
  // Edges 10^(k/2) ms for k = -4..10: 0.01 ms .. 100 s, two bins per decade.
  static const std::vector<double> edges = [] {
    std::vector<double> e;
    for (int k = -4; k <= 10; ++k) e.push_back(std::pow(10.0, k / 2.0));
    return e;
  }();
  return edges;
}

namespace {
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  // Nearest rank: deterministic and an observed value.
  auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size() - 1, i == 0 ? 0 : i - 1)];
}
}  // namespace

PlannerFigures planner_figures(const std::vector<AcceptRow>& rows) {
  PlannerFigures p;
  std::vector<double> cpu;
  for (const auto& r : rows) {
    if (!r.matched) continue;
    ++p.runs;
    p.success += r.plan_success;
    p.plan_calls += r.plan_calls;
    p.plan_cpu_ms += r.plan_cpu_ms;
    if (!r.executed) continue;
    ++p.executed;
    p.path_length += r.path_length;
    p.turns += r.turns;
    if (r.plan_calls > 0) cpu.push_back(r.plan_cpu_ms);
  }
  std::sort(cpu.begin(), cpu.end());
  p.plan_cpu_ms_p50 = quantile(cpu, 0.5);
  p.plan_cpu_ms_p90 = quantile(cpu, 0.9);
  return p;
}

Latency latency(std::vector<double> ms) {
  Latency l;
  std::sort(ms.begin(), ms.end());
  l.summary = summarize(ms);
  l.p50 = quantile(ms, 0.5);
  l.p90 = quantile(ms, 0.9);
  l.p99 = quantile(ms, 0.99);
  const auto& edges = latency_bins();
  // Bin i holds [edges[i], edges[i+1]); below the first edge goes to bin 0, above the last to
  // the last bin.
  l.histogram.assign(edges.size() - 1, 0);
  for (double x : ms) {
    auto it = std::upper_bound(edges.begin(), edges.end(), x);
    auto i = static_cast<std::size_t>(std::max<long>(0, (it - edges.begin()) - 1));
    ++l.histogram[std::min(i, l.histogram.size() - 1)];
  }
  return l;
}

Metrics compute_metrics(const ReplayResult& result) {
  Metrics m;
  m.overall = agreement(result.queries);
  for (const char* g : {"A", "B", "C"}) {
    Agreement a = agreement(result.queries, g);
    if (a.n) m.by_group[g] = std::move(a);
  }
  m.ours = figures(result.queries, true);
  m.original = figures(result.queries, false);
  m.exec = exec_agreement(result.accepts);
  m.planner = planner_figures(result.accepts);
  std::vector<double> ours, theirs;
  for (const auto& r : result.queries) {
    if (r.ours != "error") ours.push_back(r.ms);
    if (r.original_ms > 0) theirs.push_back(r.original_ms);
  }
  m.our_latency = latency(std::move(ours));
  m.original_latency = latency(std::move(theirs));
  for (const auto& d : result.defines) {
    (d.preloaded ? m.preloaded : m.defines) += 1;
    (d.preloaded ? m.preloaded_ok : m.defines_ok) += d.ok;
    if (!d.ok) ++m.define_errors[d.error_code.empty() ? "unknown" : d.error_code];
    if (!d.rule_match.empty()) ++m.rule_match[d.rule_match];
    if (!d.rule_identity.empty()) ++m.rule_identity[d.rule_identity];
    m.rule_action_hole += d.action_hole;
  }
  for (const auto& a : result.accepts) {
    m.accepted_top1 += a.matched && a.rank == 0;
    m.accepted_top3 += a.matched && a.rank >= 0 && a.rank < 3;
  }
  for (const auto& r : result.queries)
    if (r.floating) {
      ++m.floating;
      ++m.floating_by_group[r.group];
    }
  for (const auto& d : result.deletes) {
    ++m.deletes;
    m.deletes_mapped += !d.definition.empty();
    m.rules_deleted += static_cast<int>(d.deleted.size());
  }
  return m;
}

}  // namespace flipper::replay
