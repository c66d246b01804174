#pragma once
// Visiting order for the sampling planner: nearest neighbour from the robot, then 2-opt, both on
// straight-line (Euclidean) distances between cell centres, as an open path from the start.
// Points not reachable on the cell graph (walls respected, no avoid set) come last in (x, y, z)
// order, as the Planner contract requires.
#include <vector>

#include "flipper/sdk/planner.hpp"

namespace flipper::plugins::ompl {

sdk::TourResult straight_line_tour(const sdk::Geometry& geometry, sdk::Cell start,
                                   const std::vector<sdk::Cell>& points,
                                   const sdk::StopCondition& stop);

}  // namespace flipper::plugins::ompl
