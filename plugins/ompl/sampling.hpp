#pragma once
// The OMPL part of the planner: a RealVectorStateSpace of the world's dimension (cell units, so
// the centre of cell (i, j, k) is (i, j, k)), a validity checker built from the cell mask with the
// avoid set (start exempt) and, when the world offers one, its ContinuousSpace (FCL in 3-D), and
// a sub-stepping motion validator. Returns the continuous path; snapping happens elsewhere.
// Every budget counts work and every random draw follows the request's seed (docs/planners.md §3).
#include <cstdint>
#include <string>
#include <vector>

#include "cell_search.hpp"
#include "flipper/sdk/planner.hpp"
#include "snap.hpp"

namespace flipper::plugins::ompl {

enum class Algorithm { rrtconnect, rrt, prm, rrtstar };

struct SamplingSettings {
  Algorithm algorithm = Algorithm::rrtconnect;
  /// Termination-condition checks per path request (OMPL's IterationTerminationCondition: about
  /// one per planner iteration); none found within them is no_path.
  std::uint32_t max_iterations = 100000;
  double range = 0;        ///< maximum motion length in cells; 0 = OMPL's default
  std::uint32_t seed = 1;  ///< the configured seed; each request draws from request_seed()
  /// rrtstar: refinement iterations after the first solution; 0 = until max_iterations
  std::uint32_t iterations = 500;
  bool simplify = true;
};

struct SamplingOutcome {
  sdk::PlanStatus status = sdk::PlanStatus::no_path;
  std::vector<Waypoint> waypoints;  ///< start ... goal when found
  std::uint64_t iterations = 0;     ///< termination-condition checks used (the budget's unit)
  std::string message;
};

/// The seed of one path request (docs/planners.md §3): the configured seed mixed with the start
/// and goal cells (SplitMix64), folded to 32 bits, never 0. A plan depends on the configured
/// seed and the request only: not on the machine, its load or earlier requests.
std::uint32_t request_seed(std::uint32_t seed, sdk::Cell start, sdk::Cell goal);

/// Plans from search.start() to `goal` (both passable). Never throws for "no path".
SamplingOutcome sample_path(const CellSearch& search, sdk::Cell goal,
                            const SamplingSettings& settings, const sdk::StopCondition& stop);

/// "rrtconnect", ...; false if unknown.
const char* algorithm_name(Algorithm a);

}  // namespace flipper::plugins::ompl
