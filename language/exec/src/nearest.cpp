#include "nearest.hpp"

#include <cstdint>
#include <deque>
#include <vector>

namespace flipper::language::detail {

NearestGoal nearest_goal(const sdk::Geometry& g, sdk::Cell start, const sdk::Area& goals,
                         const sdk::Area* avoid, const sdk::StopCondition& stop) {
  NearestGoal out;
  if (!g.in_bounds(start)) return out;
  std::vector<std::int32_t> dist(g.cell_count(), -1);
  std::deque<sdk::Cell> queue{start};
  dist[g.index(start)] = 0;
  std::uint64_t expansions = 0;
  while (!queue.empty()) {
    const sdk::Cell u = queue.front();
    queue.pop_front();
    const std::int32_t du = dist[g.index(u)];
    // Every goal at the best distance is popped before any farther cell.
    if (out.status == sdk::PlanStatus::found && static_cast<std::size_t>(du) > out.distance) break;
    if (g.is_free(u) && sdk::areas::contains(goals, u)) {
      if (out.status != sdk::PlanStatus::found || u < out.target) out.target = u;
      out.status = sdk::PlanStatus::found;
      out.distance = static_cast<std::size_t>(du);
      continue;
    }
    if ((++expansions & 1023u) == 0 && stop.should_stop(expansions)) {
      out.status = sdk::PlanStatus::stopped;
      return out;
    }
    for (const sdk::Cell& o : g.neighbour_offsets()) {
      const sdk::Cell v = u + o;
      if (!g.is_free(v) || dist[g.index(v)] >= 0) continue;
      if (avoid != nullptr && sdk::areas::contains(*avoid, v)) continue;
      dist[g.index(v)] = du + 1;
      queue.push_back(v);
    }
  }
  return out;
}

}  // namespace flipper::language::detail
