#pragma once
/// @file planner.hpp
/// Planner plugins: shortest paths to the nearest cell of a goal area while avoiding an area,
/// and the visiting order (tour) of a set of cells, modelled on OMPL: "no plan" is a status, not
/// an exception, and every call takes a stop condition (flipper/sdk/stop.hpp: work and CPU
/// budgets, a cancel flag, a wall-clock backstop).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/stop.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
enum class PlanStatus {
  found = 0,    ///< a path / tour was produced
  no_path = 1,  ///< proven infeasible (or, for sampling planners, none found within the budget)
  stopped = 2,  ///< the stop condition fired first
  invalid = 3,  ///< bad request (e.g. empty goal set)
};
FLIPPER_SDK_API const char* to_string(PlanStatus s);

/// A path request: from `start` to the nearest reachable free cell of `goals`.
struct PathRequest {
  Cell start;
  const Area* goals = nullptr;  ///< sorted; cells that are not free are ignored
  const Area* avoid = nullptr;  ///< sorted, may be null; the start cell is always exempt
};

struct PathResult {
  PlanStatus status = PlanStatus::no_path;
  Cell target;             ///< the goal cell reached (status == found)
  std::vector<Cell> path;  ///< cells entered, in order, excluding start (empty if start is a goal)
  std::uint64_t expansions = 0;
  std::string message;  ///< a short reason when not found
};

/// A visiting order over `points`: indexes into the request's vector.
struct TourResult {
  PlanStatus status = PlanStatus::found;
  std::vector<std::size_t> order;  ///< a permutation of 0..points.size()-1
  double length = 0;               ///< path length of the tour from the start (reachable part)
};

/// What a planner can do (OMPL's PlannerSpecs): the kernel refuses incompatible world/planner
/// pairs at config time.
struct PlannerTraits {
  bool supports_2d = true;
  bool supports_3d = false;
  bool optimal = true;        ///< paths are shortest on the cell graph
  bool deterministic = true;  ///< same input, same output, whatever was asked before
  /// Sampling-based: may miss an existing path within its own budget. Every other planner
  /// must find a path to every reachable goal; the conformance kit holds a sampling planner to
  /// paths for at least 9 in 10 reachable requests.
  bool sampling = false;
};

class FLIPPER_SDK_API Planner : public Plugin {
 public:
  using Interface = Planner;
  ~Planner() override;

  /// Shortest path to the nearest reachable goal cell. Every planner: among goals it finds
  /// equally near, the smallest (x, y, z), i.e. the first of the sorted goal set
  /// (docs/core-language.md §8; the conformance kit checks it). Contract for optimal planners:
  /// path length minimal; the path itself is the one found by breadth-first search expanding
  /// neighbours in geometry.neighbour_offsets() order (first discovery wins). A budget that can
  /// change the answer counts work, never wall time (docs/planners.md §2): `stop`'s CPU budget
  /// and wall backstop only stop runaways. Never throws for "no path": returns a status.
  /// The edge cases are decided here, the same for every planner, before do_plan
  /// runs: no goals -> invalid "the goal set is empty"; a start outside the bounds -> invalid;
  /// a stop condition that already fired (CPU budget, backstop, cancel) -> stopped "stopped before
  /// planning".
  PathResult plan(const Geometry& geometry, const PathRequest& request,
                  const StopCondition& stop) const;
  /// Order in which to visit `points` starting at `start` (core-language §8 tour T for the
  /// reference planner). Unreachable points come last, in (x, y, z) order.
  /// Decided here for every planner: no points -> found, empty order; a stop that
  /// already fired -> stopped, every point in (x, y, z) order (ties by index).
  TourResult tour(const Geometry& geometry, Cell start, const std::vector<Cell>& points,
                  const StopCondition& stop) const;
  PlannerTraits traits() const { return do_traits(); }

 protected:
  virtual PathResult do_plan(const Geometry& geometry, const PathRequest& request,
                             const StopCondition& stop) const = 0;
  virtual TourResult do_tour(const Geometry& geometry, Cell start, const std::vector<Cell>& points,
                             const StopCondition& stop) const = 0;
  virtual PlannerTraits do_traits() const = 0;
};

template <>
struct KindOf<Planner> {
  static constexpr PluginKind value = PluginKind::planner;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
