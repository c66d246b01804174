// Packings (docs/naturalization.md §4.5, §4.6): which matched head spans become RHS categories.
#include <algorithm>
#include <cmath>
#include <limits>

#include "flipper/naturalization/induction.hpp"

namespace flipper::naturalization {

namespace {
// Packing totals are sums of derivation scores; sums of equal terms in another order may differ
// in the last bits, which must not decide between packings.
constexpr double kScoreTolerance = 1e-9;
}  // namespace

std::vector<Match> simple_packing(const std::vector<Match>& matches) {
  std::vector<Match> out;
  int covered = 0;  // matches are ordered by start: take the first at each free position
  for (const auto& m : matches) {
    if (!m.core_only || m.end - m.start != 1 || !is_primitive_category(m.category)) continue;
    if (m.start < covered) continue;
    out.push_back(m);
    covered = m.end;
  }
  return out;
}

double packing_score(const std::vector<Match>& packing) {
  double s = 0;
  for (const auto& m : packing) s += m.score;
  return s;
}

std::vector<Match> best_packing(const std::vector<Match>& matches, int n) {
  const std::size_t m = matches.size();
  if (m == 0) return {};
  // A packing is maximal iff no match fits entirely inside a gap between packed spans (or
  // before the first / after the last). min_end[a] = smallest end of a match starting at >= a,
  // so the gap [a, b) is free iff min_end[a] > b.
  constexpr int kNone = std::numeric_limits<int>::max();
  std::vector<int> min_end(static_cast<std::size_t>(n) + 2, kNone);
  for (const auto& x : matches)
    if (x.start >= 0 && x.start <= n)
      min_end[static_cast<std::size_t>(x.start)] =
          std::min(min_end[static_cast<std::size_t>(x.start)], x.end);
  for (int a = n - 1; a >= 0; --a)
    min_end[static_cast<std::size_t>(a)] =
        std::min(min_end[static_cast<std::size_t>(a)], min_end[static_cast<std::size_t>(a) + 1]);
  auto gap_free = [&](int a, int b) { return min_end[static_cast<std::size_t>(a)] > b; };

  // best[j]: best (total score, tie-breaks) of a valid packing prefix whose last packed span is
  // matches[j]. On equal scores the packing with fewer matches stranding a loop guard's part
  // wins (`drop green` inside `while robot has item is green {...}` would leave the guard's green
  // fixed), then the one with fewer matches the head's reading of a longer phrase splits
  // (`drop all` where the chart reads `drop all blue` as `drop` + `blue`), then the one with
  // more matches held by several body statements, then the one covering more head tokens, and
  // otherwise the first in match order (docs/naturalization.md §4.6): a phrase matched as a
  // whole (`grab blue square` as one $Action) scores what its parts (`blue`, `square`) score;
  // the parts win only when they let several statements share their holes (`walk and grab blue
  // square`), and the whole wins where nothing is shared, as the original induced (`pick green
  // item` := `pick item is green` gives `$Action item`, not `$ItemAct $Property item`).
  struct Total {
    double score = -std::numeric_limits<double>::infinity();
    int shared = 0;
    int covered = 0;    // head tokens inside packed spans
    int stranding = 0;  // matches stranding a loop guard's part
    int split = 0;      // matches the head's reading of a longer phrase splits
    bool valid() const { return score != -std::numeric_limits<double>::infinity(); }
    bool beats(const Total& o) const {
      if (!o.valid()) return valid();
      if (std::abs(score - o.score) > kScoreTolerance) return score > o.score;
      if (stranding != o.stranding) return stranding < o.stranding;
      if (split != o.split) return split < o.split;
      if (shared != o.shared) return shared > o.shared;
      return covered > o.covered;
    }
  };
  std::vector<Total> best(m);
  std::vector<int> prev(m, -1);
  for (std::size_t j = 0; j < m; ++j) {  // matches are ordered by start
    const Match& x = matches[j];
    Total base;
    if (gap_free(0, x.start)) base = {0.0, 0, 0, 0, 0};
    int from = -1;
    for (std::size_t k = 0; k < j; ++k) {
      const Match& y = matches[k];
      if (!best[k].valid() || y.end > x.start || !gap_free(y.end, x.start)) continue;
      if (best[k].beats(base)) {
        base = best[k];
        from = static_cast<int>(k);
      }
    }
    if (!base.valid()) continue;
    best[j] = {base.score + x.score, base.shared + (x.statements > 1 ? 1 : 0),
               base.covered + (x.end - x.start), base.stranding + (x.strands_loop_guard ? 1 : 0),
               base.split + (x.split_by_head ? 1 : 0)};
    prev[j] = from;
  }
  int last = -1;
  for (std::size_t j = 0; j < m; ++j) {
    if (!best[j].valid() || !gap_free(matches[j].end, n)) continue;
    if (last < 0 || best[j].beats(best[static_cast<std::size_t>(last)])) last = static_cast<int>(j);
  }
  std::vector<Match> out;
  for (int j = last; j >= 0; j = prev[static_cast<std::size_t>(j)])
    out.insert(out.begin(), matches[static_cast<std::size_t>(j)]);
  return out;
}

double best_packing_score(const std::vector<sdk::DerivationPtr>& head_chart,
                          const sdk::Program& program, int head_length) {
  return packing_score(best_packing(find_matches(head_chart, program, head_length), head_length));
}

}  // namespace flipper::naturalization
