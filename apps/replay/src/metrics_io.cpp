// metrics.json and CSV files.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "flipper/record/csv.hpp"
#include "flipper/record/out_file.hpp"
#include "flipper/replay/output.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::replay {
namespace {

using J = nlohmann::ordered_json;

J summary_json(const Summary& s) {
  return J{{"mean", s.mean}, {"min", s.min}, {"max", s.max}, {"n", s.n}};
}

template <class M>
J map_json(const M& m) {
  J j = J::object();
  for (const auto& [k, v] : m) {
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Summary>)
      j[k] = summary_json(v);
    else
      j[k] = v;
  }
  return j;
}

J agreement_json(const Agreement& a) {
  J confusion = J::object();
  for (const auto& [o, row] : a.confusion) confusion[o] = map_json(row);
  return J{{"n", a.n}, {"agree", a.agree}, {"rate", a.rate()}, {"confusion", confusion}};
}

J figures_json(const Figures& f) {
  J parts = J::array();
  for (const auto& p : f.participants)
    parts.push_back(J{{"group", p.group},
                      {"user", p.user},
                      {"queries", p.queries},
                      {"core", p.core},
                      {"induced", p.induced},
                      {"failed", p.failed},
                      {"tokens_all", p.tokens_all},
                      {"tokens_successful", p.tokens_successful},
                      {"by_self", p.by_self},
                      {"by_others", p.by_others}});
  return J{{"tokens_successful", map_json(f.tokens_successful)},
           {"tokens_all", map_json(f.tokens_all)},
           {"tokens_successful_sum", map_json(f.tokens_successful_sum)},
           {"tokens_all_sum", map_json(f.tokens_all_sum)},
           {"induced", map_json(f.induced)},
           {"core", map_json(f.core)},
           {"others", summary_json(f.others)},
           {"self", summary_json(f.self)},
           {"participants", parts}};
}

J latency_json(const Latency& l) {
  return J{{"summary", summary_json(l.summary)},
           {"p50", l.p50},
           {"p90", l.p90},
           {"p99", l.p99},
           {"bin_edges_ms", latency_bins()},
           {"histogram", l.histogram}};
}

using record::OutFile;
std::string csv(const std::string& s) {
  return record::csv_field(s);
}

}  // namespace

nlohmann::ordered_json metrics_json(const Metrics& m) {
  J groups = J::object();
  for (const auto& [g, a] : m.by_group) groups[g] = agreement_json(a);
  const auto& e = m.exec;
  J metric{{"agreement", agreement_json(m.overall)},
           {"agreement_by_group", groups},
           {"figures_ours", figures_json(m.ours)},
           {"figures_original", figures_json(m.original)},
           {"execution", J{{"accepts", e.accepts},
                           {"matched", e.matched},
                           {"executed", e.executed},
                           {"compared", e.compared},
                           {"robot", e.robot},
                           {"held", e.held},
                           {"floor", e.floor},
                           {"all", e.all},
                           {"classified", e.classified},
                           {"unexplained", e.unexplained},
                           {"classes", map_json(e.classes)},
                           {"not_executed", map_json(e.not_executed)}}},
           {"latency_ours_ms", latency_json(m.our_latency)},
           {"latency_original_ms", latency_json(m.original_latency)},
           {"definitions", J{{"defines", m.defines},
                             {"ok", m.defines_ok},
                             {"preloaded", m.preloaded},
                             {"preloaded_ok", m.preloaded_ok},
                             {"errors", map_json(m.define_errors)},
                             {"rule_match", map_json(m.rule_match)}}},
           {"deletions", J{{"deletes", m.deletes},
                           {"mapped", m.deletes_mapped},
                           {"rules_deleted", m.rules_deleted}}}};
  metric["floating_top"] = J{{"all", m.floating}, {"by_group", map_json(m.floating_by_group)}};
  metric["accepted_rank"] = J{{"top1", m.accepted_top1}, {"top3", m.accepted_top3}};
  const PlannerFigures& pl = m.planner;
  metric["planner"] = J{{"runs", pl.runs},
                        {"executed", pl.executed},
                        {"success", pl.success},
                        {"path_length", pl.path_length},
                        {"turns", pl.turns},
                        {"plan_calls", pl.plan_calls},
                        {"plan_cpu_ms", pl.plan_cpu_ms},
                        {"plan_cpu_ms_p50", pl.plan_cpu_ms_p50},
                        {"plan_cpu_ms_p90", pl.plan_cpu_ms_p90}};
  return metric;
}

void write_metrics(const std::string& dir, const ReplayResult& result, const Metrics& m) {
  std::filesystem::create_directories(dir);
  OutFile json(dir + "/metrics.json");
  json << metrics_json(m).dump(1) << "\n";
  json.close();

  OutFile q(dir + "/queries.csv");
  q << "qid,run,group,user,phase,in_authors_tables,tokens,original,ours,agree,original_author,"
       "our_author,original_parses,our_candidates,ms,original_ms,utterance\n";
  for (const auto& r : result.queries)
    q << csv(r.qid) << ',' << csv(r.run) << ',' << r.group << ',' << csv(r.user) << ',' << r.phase
      << ',' << r.in_authors_tables << ',' << r.tokens << ',' << r.original << ',' << r.ours << ','
      << (as_original_status(r.ours) == r.original) << ',' << r.original_author << ','
      << r.our_author << ',' << r.original_parses << ',' << r.our_candidates << ',' << r.ms << ','
      << r.original_ms << ',' << csv(r.utterance) << "\n";

  OutFile p(dir + "/participants.csv");
  p << "group,user,queries,agree,ours_core,ours_induced,ours_failed,orig_core,orig_induced,"
       "orig_failed,ours_tokens_successful,orig_tokens_successful,tokens_all,ours_by_self,"
       "ours_by_others,orig_by_self,orig_by_others\n";
  for (std::size_t i = 0; i < m.ours.participants.size(); ++i) {
    const auto& a = m.ours.participants[i];
    const auto& b = m.original.participants[i];  // same filter, same order
    p << a.group << ',' << csv(a.user) << ',' << a.queries << ',' << a.agree << ',' << a.core << ','
      << a.induced << ',' << a.failed << ',' << b.core << ',' << b.induced << ',' << b.failed << ','
      << a.tokens_successful << ',' << b.tokens_successful << ',' << a.tokens_all << ','
      << a.by_self << ',' << a.by_others << ',' << b.by_self << ',' << b.by_others << "\n";
  }

  OutFile g(dir + "/groups.csv");
  g << "group,queries,agree,rate,ours_tokens_successful_mean,orig_tokens_successful_mean,"
       "tokens_all_mean,participants\n";
  for (const auto& [name, a] : m.by_group) {
    const std::string& group = name;  // clang 14 cannot capture a structured binding
    auto mean = [&](const std::map<std::string, Summary>& s) {
      auto it = s.find(group);
      return it == s.end() ? 0.0 : it->second.mean;
    };
    auto it = m.ours.tokens_all.find(name);
    g << name << ',' << a.n << ',' << a.agree << ',' << a.rate() << ','
      << mean(m.ours.tokens_successful) << ',' << mean(m.original.tokens_successful) << ','
      << mean(m.ours.tokens_all) << ',' << (it == m.ours.tokens_all.end() ? 0 : it->second.n)
      << "\n";
  }

  OutFile acc(dir + "/accepts.csv");
  acc << "qid,run,group,user,matched,rank,executed,compared,robot,held,floor,class,note,"
         "plan_success,path_length,turns,plan_calls,plan_cpu_ms\n";
  for (const auto& r : result.accepts)
    acc << csv(r.qid) << ',' << csv(r.run) << ',' << r.group << ',' << csv(r.user) << ','
        << r.matched << ',' << r.rank << ',' << r.executed << ',' << r.compared << ',' << r.robot
        << ',' << r.held << ',' << r.floor << ',' << r.diff << ',' << csv(r.note) << ','
        << r.plan_success << ',' << r.path_length << ',' << r.turns << ',' << r.plan_calls << ','
        << r.plan_cpu_ms << "\n";

  OutFile d(dir + "/definitions.csv");
  d << "qid,run,user,preloaded,ok,error,rules,rule_match,rule_identity,action_hole,head\n";
  for (const auto& r : result.defines)
    d << csv(r.qid) << ',' << csv(r.run) << ',' << csv(r.user) << ',' << r.preloaded << ',' << r.ok
      << ',' << r.error_code << ',' << r.rules << ',' << r.rule_match << ',' << r.rule_identity
      << ',' << r.action_hole << ',' << csv(r.head) << "\n";
  OutFile del(dir + "/deletions.csv");
  del << "qid,run,user,rule_index,definition,deleted,note\n";
  for (const auto& r : result.deletes) {
    std::string ids;
    for (const auto& id : r.deleted) ids += (ids.empty() ? "" : " ") + id;
    del << csv(r.qid) << ',' << csv(r.run) << ',' << csv(r.user) << ',' << r.rule_index << ','
        << csv(r.definition) << ',' << csv(ids) << ',' << csv(r.note) << "\n";
  }
  for (OutFile* f : {&q, &p, &g, &acc, &d, &del}) f->close();
}

}  // namespace flipper::replay
