#pragma once
// The OMPL part of the planner: a RealVectorStateSpace of the world's dimension (cell units, so
// the centre of cell (i, j, k) is (i, j, k)), a validity checker built from the cell mask with the
// avoid set (start exempt) and, when the world offers one, its ContinuousSpace (FCL in 3-D), and
// a sub-stepping motion validator. Returns the continuous path; snapping happens elsewhere.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "cell_search.hpp"
#include "flipper/sdk/planner.hpp"
#include "snap.hpp"

namespace flipper::omplplanner {

enum class Algorithm { rrtconnect, rrt, prm, rrtstar };

struct SamplingSettings {
  Algorithm algorithm = Algorithm::rrtconnect;
  std::chrono::milliseconds time_budget{500};
  double range = 0;        ///< maximum motion length in cells; 0 = OMPL's default
  std::uint32_t seed = 1;  ///< 0 = not reseeded (non-deterministic)
  std::uint32_t iterations =
      500;  ///< rrtstar: refinement iterations after the first solution; 0 = time only
  bool simplify = true;
};

struct SamplingOutcome {
  sdk::PlanStatus status = sdk::PlanStatus::no_path;
  std::vector<Waypoint> waypoints;  ///< start ... goal when found
  std::uint64_t states = 0;         ///< states in the planner's graph
  std::string message;
};

/// Plans from search.start() to `goal` (both passable). Never throws for "no path".
SamplingOutcome sample_path(const CellSearch& search, sdk::Cell goal,
                            const SamplingSettings& settings, const sdk::StopCondition& stop);

/// "rrtconnect", ...; false if unknown.
bool parse_algorithm(const std::string& name, Algorithm& out);
const char* algorithm_name(Algorithm a);

}  // namespace flipper::omplplanner
