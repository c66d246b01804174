// The Markdown tables a report shares with `flipper replay --print`, read from the run's figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "flipper/record/compare.hpp"
#include "flipper/replay/output.hpp"

namespace flipper::replay {

std::string one_decimal(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

std::string duration_text(double ms) {
  char b[32];
  if (ms == 0) return "0";
  if (ms < 0.01)
    std::snprintf(b, sizeof b, "%.1f µs", ms * 1000);
  else if (ms < 1)
    std::snprintf(b, sizeof b, "%.0f µs", ms * 1000);
  else if (ms < 100)
    std::snprintf(b, sizeof b, "%.2f ms", ms);
  else
    std::snprintf(b, sizeof b, "%.0f ms", ms);
  return b;
}

namespace {

// A percentage with one decimal, as rates are shown ("97.0").
std::string pct(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

double or_zero(const record::FigureTable& t, const std::string& v, const std::string& source,
               const std::string& group, const std::string& metric) {
  return t.find(v, source, group, metric).value_or(0.0);
}

}  // namespace

std::string variants_table(const record::FigureTable& t,
                           const std::vector<record::VariantInfo>& variants) {
  std::ostringstream o;
  o << "| variant | agreement all / A / B / C | Core → core | Nothing → reading | floating tops | "
       "accepted: first / top 3 / matched | tokens succ. A / B / C | induced B / C | core B / "
       "C |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& v : variants) {
    const std::string& n = v.name;
    auto f = [&](const std::string& source, const std::string& group, const std::string& metric) {
      return or_zero(t, n, source, group, metric);
    };
    o << "| " << n << " | " << pct(f("ours", "all", "agreement")) << " / "
      << pct(f("ours", "A", "agreement")) << " / " << pct(f("ours", "B", "agreement")) << " / "
      << pct(f("ours", "C", "agreement")) << " % | "
      << record::show_value(f("ours", "Core->core", "confusion")) << " / "
      << record::show_value(f("ours", "Core", "original_status")) << " | "
      << record::show_value(f("ours", "Nothing->core", "confusion") +
                            f("ours", "Nothing->induced", "confusion"))
      << " / " << record::show_value(f("ours", "Nothing", "original_status")) << " | "
      << record::show_value(f("ours", "all", "floating_tops")) << " | "
      << record::show_value(f("ours", "all", "accepted_first")) << " / "
      << record::show_value(f("ours", "all", "accepted_top3")) << " / "
      << record::show_value(f("ours", "all", "accepts_matched")) << " | "
      << one_decimal(f("ours", "A", "tokens_successful_mean")) << " / "
      << one_decimal(f("ours", "B", "tokens_successful_mean")) << " / "
      << one_decimal(f("ours", "C", "tokens_successful_mean")) << " | "
      << one_decimal(f("ours", "B", "induced_mean")) << " / "
      << one_decimal(f("ours", "C", "induced_mean")) << " | "
      << one_decimal(f("ours", "B", "core_mean")) << " / "
      << one_decimal(f("ours", "C", "core_mean")) << " |\n";
  }
  return o.str();
}

namespace {

// One line per variant (its name first when there are several); `line(o, v, f)` writes it, with
// f(group, metric) a figure of ours as shown.
template <class Line>
std::string per_variant(const record::FigureTable& t,
                        const std::vector<record::VariantInfo>& variants, Line line) {
  std::ostringstream o;
  for (const auto& v : variants) {
    auto f = [&](const std::string& group, const std::string& metric) {
      return record::show_value(or_zero(t, v.name, "ours", group, metric));
    };
    if (variants.size() > 1) o << "`" << v.name << "`: ";
    line(o, v, f);
  }
  return o.str();
}

}  // namespace

std::string headline_text(const record::FigureTable& t,
                          const std::vector<record::VariantInfo>& variants) {
  return per_variant(t, variants, [&](std::ostream& o, const record::VariantInfo& v, auto f) {
    o << "status agreement " << f("all", "agree") << " / " << f("all", "queries") << " ("
      << pct(or_zero(t, v.name, "ours", "all", "agreement")) << " %); accepted programs among ours "
      << f("all", "accepts_matched") << " / " << f("all", "accepts")
      << ", executions agreeing with the logged next world " << f("all", "exec_all_agree") << " / "
      << f("all", "accepts_compared") << ".\n";
  });
}

std::string oracles_text(const record::FigureTable& t,
                         const std::vector<record::VariantInfo>& variants) {
  return per_variant(t, variants, [](std::ostream& o, const record::VariantInfo&, auto f) {
    o << "induced rules against the original's, per definition: " << f("identical", "rule_match")
      << " identical, " << f("subset", "rule_match") << " subset, " << f("overlap", "rule_match")
      << " overlap, " << f("missing", "rule_match") << " missing of "
      << f("all", "rule_match_compared")
      << "; execution differences no tie rule explains: " << f("all", "unexplained") << " of "
      << f("all", "accepts_classified") << " classified accepts.\n";
  });
}

std::string rules_text(const record::FigureTable& t,
                       const std::vector<record::VariantInfo>& variants) {
  return per_variant(t, variants, [&](std::ostream& o, const record::VariantInfo& v, auto f) {
    auto n = [&](const char* cls) { return or_zero(t, v.name, "ours", cls, "rule_identity"); };
    const double all = or_zero(t, v.name, "ours", "all", "rule_identity_compared");
    const double equal = n("identical") + n("present");
    o << "induced rules equal to the original's (identical or already present), per definition: "
      << record::show_value(equal) << " / " << record::show_value(all) << " ("
      << pct(all > 0 ? 100 * equal / all : 0) << " %): " << f("identical", "rule_identity")
      << " identical, " << f("present", "rule_identity") << " already present; differing "
      << f("subset", "rule_identity") << " subset, " << f("superset", "rule_identity")
      << " superset, " << f("overlap", "rule_identity") << " overlap, "
      << f("disjoint", "rule_identity") << " disjoint; the original's $Action hole missing in "
      << f("all", "rule_action_hole") << ".\n";
  });
}

std::string planner_table(const record::FigureTable& t,
                          const std::vector<record::VariantInfo>& variants) {
  std::ostringstream o;
  o << "| variant | programs run | success | path length (cells, mean) | turns (mean) | planner "
       "calls | plan CPU p50 / p90 / total |\n|---|---|---|---|---|---|---|\n";
  for (const auto& v : variants) {
    auto f = [&](const std::string& metric) { return or_zero(t, v.name, "ours", "all", metric); };
    char mean[64];
    std::snprintf(mean, sizeof mean, "%.2f | %.2f", f("path_length_mean"), f("turns_mean"));
    o << "| " << v.name << " | " << record::show_value(f("plan_runs")) << " | "
      << record::show_value(f("plan_success")) << " (" << pct(f("plan_success_rate")) << " %) | "
      << mean << " | " << record::show_value(f("plan_calls")) << " | "
      << duration_text(f("plan_cpu_p50")) << " / " << duration_text(f("plan_cpu_p90")) << " / "
      << duration_text(f("plan_cpu_sum")) << " |\n";
  }
  return o.str();
}

std::string seeds_table(const std::vector<record::Figure>& figures,
                        const std::vector<record::VariantInfo>& variants) {
  bool seeded = false;
  for (const auto& v : variants) seeded = seeded || !v.seed.empty();
  if (!seeded) return "";
  static const std::pair<const char*, const char*> kShown[] = {
      {"all", "agreement"},        {"all", "exec_all_agree"}, {"all", "plan_success_rate"},
      {"all", "path_length_mean"}, {"all", "turns_mean"},     {"all", "plan_cpu_p50"}};
  std::ostringstream o;
  o << "| condition | seeds | agreement (%) | executions agreeing | planner success (%) | path "
       "length | turns | plan CPU p50 (ms, timing) |\n|---|---|---|---|---|---|---|---|\n";
  const auto spreads = record::spread_over_seeds(figures, variants);
  std::vector<std::string> conditions;
  for (const auto& v : variants)
    if (std::find(conditions.begin(), conditions.end(), v.condition) == conditions.end())
      conditions.push_back(v.condition);
  for (const auto& c : conditions) {
    int n = 0;
    for (const auto& v : variants) n += v.condition == c;
    o << "| " << c << " | " << n;
    for (const auto& [group, metric] : kShown) {
      std::string cell = "–";
      for (const auto& s : spreads)
        if (s.condition == c && s.source == "ours" && s.group == group && s.metric == metric) {
          char b[96];
          std::snprintf(b, sizeof b, "%.4g ± %.2g (%.4g–%.4g)", s.mean, s.sd, s.min, s.max);
          cell = b;
        }
      o << " | " << cell;
    }
    o << " |\n";
  }
  return o.str();
}

}  // namespace flipper::replay
