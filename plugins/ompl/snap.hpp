#pragma once
// Snapping a continuous path onto the cell graph.
#include <array>
#include <vector>

#include "cell_search.hpp"

namespace flipper::plugins::ompl {

using Waypoint = std::array<double, 3>;

/// Turns the continuous `waypoints` (cell units, from the start towards `goal`) into cells
/// entered one neighbour step at a time (excluding the start), ending at `goal`. Each segment is
/// sampled every 1/8 cell and rounded to cells; passable cells become anchors; consecutive
/// anchors that are not neighbours (a diagonal, or a corner the straight line cut) are joined by
/// a short breadth-first search near both, and anchors it cannot join are skipped. Finally the
/// last anchor is joined to `goal` and loops are cut out. Precondition: goal reachable.
/// Returns false only if the goal could not be joined (which the precondition excludes).
bool snap_path(const std::vector<Waypoint>& waypoints, sdk::Cell goal, CellSearch& search,
               std::vector<sdk::Cell>& path);

}  // namespace flipper::plugins::ompl
