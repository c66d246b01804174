#include "tour.hpp"

#include <algorithm>
#include <numeric>

#include "cell_search.hpp"

namespace flipper::plugins::ompl {

using sdk::Cell;

constexpr int kMaxPasses = 1000;  // 2-opt passes over the whole order, at most

sdk::TourResult straight_line_tour(const sdk::Geometry& geometry, Cell start,
                                   const std::vector<Cell>& points,
                                   const sdk::StopCondition& stop) {
  sdk::TourResult result;
  const CellSearch reach(geometry, nullptr, start);
  std::vector<std::size_t> todo, unreachable;
  for (std::size_t i = 0; i < points.size(); ++i)
    (reach.reachable(points[i]) ? todo : unreachable).push_back(i);
  auto by_cell = [&](std::size_t a, std::size_t b) {
    return points[a] != points[b] ? points[a] < points[b] : a < b;
  };
  std::sort(unreachable.begin(), unreachable.end(), by_cell);

  // The caller's stop (a runaway deadline or a cancel) gives `stopped`, never a shorter-worked
  // order: every point in (x, y, z) order, the reachable ones first. The work itself is counted
  // (one nearest-neighbour pass, at most kMaxPasses 2-opt passes), so an order never depends on
  // the clock (docs/planners.md §3).
  auto stopped = [&] {
    std::sort(todo.begin(), todo.end(), by_cell);
    result.order = todo;
    result.order.insert(result.order.end(), unreachable.begin(), unreachable.end());
    result.status = sdk::PlanStatus::stopped;
    result.length = 0;
    return result;
  };
  if (stop.should_stop(0)) return stopped();

  // Nearest neighbour; ties by (x, y, z), then by index.
  std::vector<std::size_t> order;
  order.reserve(todo.size());
  std::vector<bool> used(todo.size(), false);
  Cell at = start;
  for (std::size_t n = 0; n < todo.size(); ++n) {
    if (stop.expired()) return stopped();
    std::size_t best = todo.size();
    double best_d = 0;
    for (std::size_t k = 0; k < todo.size(); ++k) {
      if (used[k]) continue;
      const double d = distance(at, points[todo[k]]);
      if (best == todo.size() || d < best_d - 1e-12 ||
          (d <= best_d + 1e-12 && by_cell(todo[k], todo[best]))) {
        best = k;
        best_d = d;
      }
    }
    used[best] = true;
    order.push_back(todo[best]);
    at = points[todo[best]];
  }

  // 2-opt on the open path start -> order[0] -> ... (reversing order[i..j]).
  auto p = [&](std::size_t k) { return k == 0 ? start : points[order[k - 1]]; };  // k in 0..n
  const std::size_t n = order.size();
  bool improved = true;
  for (int pass = 0; improved && pass < kMaxPasses; ++pass) {
    improved = false;
    for (std::size_t i = 1; i + 1 <= n; ++i) {
      if (stop.expired()) return stopped();
      for (std::size_t j = i + 1; j <= n; ++j) {
        double delta = distance(p(i - 1), p(j)) - distance(p(i - 1), p(i));
        if (j < n) delta += distance(p(i), p(j + 1)) - distance(p(j), p(j + 1));
        if (delta < -1e-9) {
          std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i - 1),
                       order.begin() + static_cast<std::ptrdiff_t>(j));
          improved = true;
        }
      }
    }
  }
  for (std::size_t k = 1; k <= n; ++k) result.length += distance(p(k - 1), p(k));
  order.insert(order.end(), unreachable.begin(), unreachable.end());
  result.order = std::move(order);
  result.status = sdk::PlanStatus::found;
  return result;
}

}  // namespace flipper::plugins::ompl
