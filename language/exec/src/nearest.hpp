#pragma once
// The nearest goal by path (core-language §4.4, §8), decided by the executor for planners that do
// not promise shortest paths (PlannerTraits::optimal false, e.g. sampling planners), so that
// `visit` of an area or collection picks the same goal whatever the planner: which goal is
// semantics, how to get there is planning.
#include <cstddef>

#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::language::detail {

struct NearestGoal {
  sdk::PlanStatus status = sdk::PlanStatus::no_path;  ///< found, no_path or stopped
  sdk::Cell target;                                   ///< the nearest free goal (found)
  std::size_t distance = 0;                           ///< its path length in steps
};

/// Breadth-first search over free cells from `start` (exempt from `avoid`) to the free cells of
/// `goals` (sorted); the smallest distance wins, ties by the smallest (x, y, z).
NearestGoal nearest_goal(const sdk::Geometry& g, sdk::Cell start, const sdk::Area& goals,
                         const sdk::Area* avoid, const sdk::StopCondition& stop);

}  // namespace flipper::language::detail
