// Two runs side by side (compare.hpp).
#include "flipper/record/compare.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

namespace flipper::record {
namespace {

std::string spread_text(const Spread& s) {
  if (s.n == 1) return show_value(s.mean);
  return show_value(s.mean) + " ± " + show_value(s.sd) + " (" + show_value(s.min) + "–" +
         show_value(s.max) + ", n=" + std::to_string(s.n) + ")";
}

std::string signed_value(double v) {
  return (v > 0 ? "+" : "") + show_value(v);
}

using Key = std::tuple<std::string, std::string, std::string, std::string>;
std::map<Key, Spread> by_key(const std::vector<Spread>& spreads) {
  std::map<Key, Spread> out;
  for (const auto& s : spreads) out[{s.condition, s.source, s.group, s.metric}] = s;
  return out;
}

bool same(const Spread& a, const Spread& b) {
  return a.n == b.n && a.mean == b.mean && a.min == b.min && a.max == b.max && a.sd == b.sd;
}

}  // namespace

std::string show_value(double value) {
  if (std::isfinite(value) && value == std::round(value) && std::fabs(value) < 1e15) {
    char b[32];
    std::snprintf(b, sizeof b, "%.0f", value);
    return b;
  }
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", value);
  return b;
}

RunFigures read_run_figures(const std::string& run_dir) {
  return {run_dir, read_figures(run_dir + "/figures.csv"), read_variants(run_dir)};
}

std::string compare_runs(const RunFigures& a, const RunFigures& b, bool all) {
  const auto sa = spread_over_seeds(a.figures, a.variants);
  const auto sb = spread_over_seeds(b.figures, b.variants);
  const auto ma = by_key(sa), mb = by_key(sb);
  std::vector<std::string> conditions;
  std::set<std::string> seen;
  for (const auto* list : {&sa, &sb})
    for (const auto& s : *list)
      if (seen.insert(s.condition).second) conditions.push_back(s.condition);

  std::ostringstream o;
  o << "# " << a.label << " (A) and " << b.label << " (B)\n\n";
  std::size_t compared = 0, differing = 0, timing_rows = 0;
  std::vector<std::string> only_a, only_b;
  for (const auto& condition : conditions) {
    std::vector<std::string> rows, timing;
    bool in_a = false, in_b = false;
    int seeds_a = 0, seeds_b = 0;
    std::set<Key> keys;
    for (const auto& [k, s] : ma)
      if (std::get<0>(k) == condition)
        keys.insert(k), in_a = true, seeds_a = std::max(seeds_a, s.n);
    for (const auto& [k, s] : mb)
      if (std::get<0>(k) == condition)
        keys.insert(k), in_b = true, seeds_b = std::max(seeds_b, s.n);
    if (!in_a || !in_b) {
      (in_a ? only_a : only_b).push_back(condition);
      continue;
    }
    for (const auto& k : keys) {
      auto ia = ma.find(k), ib = mb.find(k);
      const std::string figure = std::get<1>(k) + " / " + std::get<2>(k) + " / " + std::get<3>(k);
      const std::string unit = (ia != ma.end() ? ia->second.unit : ib->second.unit);
      const bool is_timing =
          (ia != ma.end() && ia->second.timing) || (ib != mb.end() && ib->second.timing);
      std::string row = "| " + figure + (unit.empty() ? "" : " (" + unit + ")") + " | ";
      row += (ia != ma.end() ? spread_text(ia->second) : "–") + " | ";
      row += (ib != mb.end() ? spread_text(ib->second) : "–") + " | ";
      const bool both = ia != ma.end() && ib != mb.end();
      row += (both ? signed_value(ib->second.mean - ia->second.mean) : "–") + " |";
      const bool differs = !both || !same(ia->second, ib->second);
      if (is_timing) {
        ++timing_rows;
        if (all || differs) timing.push_back(row);
        continue;
      }
      ++compared;
      differing += differs;
      if (all || differs) rows.push_back(row);
    }
    o << "## " << condition;
    if (seeds_a > 1 || seeds_b > 1)
      o << " (over seeds: " << seeds_a << " in A, " << seeds_b << " in B)";
    o << "\n\n";
    if (rows.empty()) {
      o << "Every figure is the same in A and B.\n\n";
    } else {
      o << "| figure (source / group / metric) | A | B | B − A |\n|---|---|---|---|\n";
      for (const auto& r : rows) o << r << "\n";
      o << "\n";
    }
    if (!timing.empty()) {
      o << "Timing figures (they measure time: they differ between runs and are not "
           "differences):\n\n| figure | A | B | B − A |\n|---|---|---|---|\n";
      for (const auto& r : timing) o << r << "\n";
      o << "\n";
    }
  }
  if (!only_a.empty() || !only_b.empty()) {
    o << "Only in A:";
    for (const auto& c : only_a) o << " `" << c << "`";
    o << (only_a.empty() ? " none" : "") << ". Only in B:";
    for (const auto& c : only_b) o << " `" << c << "`";
    o << (only_b.empty() ? " none" : "") << ".\n\n";
  }
  o << differing << " of " << compared << " figures differ";
  if (timing_rows) o << "; timing figures (not compared): " << timing_rows;
  o << ".\n";
  return o.str();
}

}  // namespace flipper::record
