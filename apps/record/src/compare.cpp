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

// Natural order: digit runs compare as numbers ("rank_2" before "rank_10", "seed=9" before
// "seed=10"), everything else as text.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && digit(a[ei])) ++ei;
      while (ej < b.size() && digit(b[ej])) ++ej;
      std::size_t zi = i, zj = j;  // leading zeros do not count
      while (zi + 1 < ei && a[zi] == '0') ++zi;
      while (zj + 1 < ej && b[zj] == '0') ++zj;
      if (ei - zi != ej - zj) return ei - zi < ej - zj;
      const int c = a.compare(zi, ei - zi, b, zj, ej - zj);
      if (c != 0) return c < 0;
      i = ei;
      j = ej;
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

struct NaturalKeyLess {
  bool operator()(const Key& x, const Key& y) const {
    const std::string* xs[] = {&std::get<0>(x), &std::get<1>(x), &std::get<2>(x), &std::get<3>(x)};
    const std::string* ys[] = {&std::get<0>(y), &std::get<1>(y), &std::get<2>(y), &std::get<3>(y)};
    for (int k = 0; k < 4; ++k) {
      if (natural_less(*xs[k], *ys[k])) return true;
      if (natural_less(*ys[k], *xs[k])) return false;
    }
    return false;
  }
};

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
  char b[64];
  std::snprintf(b, sizeof b, "%.4g", value);
  // Large values keep their digits (123456.7, never 1.235e+05).
  if (std::isfinite(value) && std::fabs(value) >= 1e4 && std::fabs(value) < 1e15)
    std::snprintf(b, sizeof b, "%.1f", value);
  return b;
}

RunFigures read_run_figures(const std::string& run_dir) {
  return {run_dir, read_figures(run_dir + "/figures.csv"), read_variants(run_dir)};
}

std::string compare_runs(const RunFigures& a, const RunFigures& b, bool all,
                         ComparisonCounts* counts) {
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
    std::set<Key, NaturalKeyLess> keys;
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
  if (compared == 0) {
    o << "Nothing compared: A and B share no figure of one condition";
    if (timing_rows) o << " (timing figures are never compared: " << timing_rows << ")";
    o << ". Compare runs of the same experiment, or variants of the same names.\n";
  } else {
    o << differing << " of " << compared << " figures differ";
    if (timing_rows) o << "; timing figures (not compared): " << timing_rows;
    o << ".\n";
  }
  if (counts != nullptr) *counts = {compared, differing};
  return o.str();
}

}  // namespace flipper::record
