// The ompl planner plugin: sampling-based paths (RRT-Connect by default) in the continuous space
// of any world, snapped back onto the world's cell graph.
//
// Decisions (documented for users of the plugin):
// - Goal: among the goal cells that are free, outside the avoid set and connected to the start
//   on the cell graph, the nearest by straight-line distance (ties: smallest x, y, z). The
//   connectivity check is one flood fill per request; it makes an infeasible request answer
//   `no_path` at once instead of sampling until the time budget runs out.
// - Path: the planner's path, simplified (vertex reduction + shortcuts), is snapped to cells: a
//   sequence of neighbour steps (4/6-neighbourhood) through free, non-avoided cells, with short
//   grid searches where the straight line cut a corner. Not shortest: traits().optimal is false.
// - Tour: nearest neighbour + 2-opt on straight-line distances (see tour.hpp).
// - Determinism (docs/planners.md §3): every budget counts work (max_iterations termination
//   checks per request; rrtstar's refinement `iterations`), never wall time, and OMPL is reseeded
//   before every request from request_seed(seed, start, goal); prm runs on one thread in counted
//   slices (serial_prm.hpp). Same config, same request => the same path on any machine, under any
//   load, whatever was planned before. The caller's deadline only stops runaways: `stopped`.
#include <ompl/util/Console.h>

#include "cell_search.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/plugin.hpp"
#include "sampling.hpp"
#include "snap.hpp"
#include "tour.hpp"

namespace flipper::plugins::ompl {

using sdk::Cell;
using sdk::PlanStatus;

namespace param = sdk::param;

constexpr const char* kTimeBudgetRetired =
    "it was a wall-clock budget per path request, so the plan depended on the machine's load; "
    "the budget counts work now: max_iterations (termination checks per path request, default "
    "100000; docs/planners.md §3)";
// In the order of Algorithm's enumerators (sampling.hpp).
constexpr param::Choice<Algorithm, 4> kPlanner{
    "planner", Algorithm::rrtconnect, {"rrtconnect", "rrt", "prm", "rrtstar"}, "OMPL planner"};
constexpr param::Int<std::uint32_t> kMaxIterations{
    "max_iterations", 100000, 1, 100000000,
    "work budget per path request: termination checks (OMPL's IterationTerminationCondition, "
    "about one per planner iteration); no path within them is no_path"};
constexpr param::Double kRange{"range", 0.0, 0.0, 1e6,
                               "maximum motion length in cells (0: OMPL's default)"};
constexpr param::Int<std::uint32_t> kSeed{
    "seed", 1, 1, 4294967295U,
    "random seed; each request derives its own from it, the start and the goal (0, unseeded, is "
    "not offered: plans repeat for the same config and seed, docs/planners.md §3)"};
constexpr param::Int<std::uint32_t> kIterations{
    "iterations", 500, 0, 100000000,
    "rrtstar: refinement iterations after the first solution (0: until max_iterations)"};
constexpr param::Bool kSimplify{"simplify", true,
                                "simplify the sampled path before snapping it to cells"};

class OmplPlanner final : public sdk::Planner {
 public:
  explicit OmplPlanner(const sdk::Params& p) {
    if (p.has("time_budget_ms"))  // a host that did not validate the params (the kernel does)
      throw sdk::Error(sdk::codes::kBadConfig,
                       std::string("ompl: time_budget_ms is retired: ") + kTimeBudgetRetired);
    settings_.algorithm = param::get(p, kPlanner);
    settings_.max_iterations = param::get(p, kMaxIterations);
    settings_.range = param::get(p, kRange);
    settings_.seed = param::get(p, kSeed);
    settings_.iterations = param::get(p, kIterations);
    settings_.simplify = param::get(p, kSimplify);
    ::ompl::msg::setLogLevel(::ompl::msg::LOG_NONE);  // failures come back as statuses instead
  }

  static sdk::ParamSchema schema() {
    sdk::ParamSchema s =
        param::schema(kPlanner, kMaxIterations, kRange, kSeed, kIterations, kSimplify);
    s.add_retired("time_budget_ms", kTimeBudgetRetired);
    return s;
  }

 protected:
  sdk::PathResult do_plan(const sdk::Geometry& g, const sdk::PathRequest& request,
                          const sdk::StopCondition& stop) const override {
    // Goals present, start in bounds, stop not yet fired: Planner::plan checked.
    sdk::PathResult r;
    const Cell start = request.start;
    if (!g.is_free(start)) {
      r.status = PlanStatus::invalid;
      r.message = "start " + sdk::to_string(start, g.dims()) + " is not a free cell";
      return r;
    }
    CellSearch search(g, request.avoid, start);
    const Cell* goal = nullptr;
    double best = 0;
    bool any_passable = false;
    for (const Cell& c : *request.goals) {
      if (c == start) {  // already there (the start is exempt from the avoid set)
        r.status = PlanStatus::found;
        r.target = start;
        return r;
      }
      if (!search.passable(c)) continue;
      any_passable = true;
      if (!search.reachable(c)) continue;
      const double d = distance(start, c);
      if (goal == nullptr || d < best - 1e-12) {  // goals are sorted: ties keep the smallest
        goal = &c;
        best = d;
      }
    }
    if (goal == nullptr) {
      r.status = PlanStatus::no_path;
      r.message = any_passable ? "no goal cell is reachable from " + sdk::to_string(start, g.dims())
                               : "no goal cell is free and outside the avoid set";
      return r;
    }
    SamplingOutcome sampled = sample_path(search, *goal, settings_, stop);
    // The budget's unit (termination checks), also what a caller's max_expansions bounds.
    r.expansions = sampled.iterations;
    if (sampled.status != PlanStatus::found) {
      r.status = sampled.status;
      r.message = sampled.message + " to " + sdk::to_string(*goal, g.dims());
      return r;
    }
    if (!snap_path(sampled.waypoints, *goal, search, r.path)) {  // excluded by the flood fill
      r.status = PlanStatus::no_path;
      r.message = "could not snap the path to cells";
      r.path.clear();
      return r;
    }
    r.status = PlanStatus::found;
    r.target = *goal;
    return r;
  }

  sdk::TourResult do_tour(const sdk::Geometry& g, Cell start, const std::vector<Cell>& points,
                          const sdk::StopCondition& stop) const override {
    return straight_line_tour(g, start, points, stop);
  }

  sdk::PlannerTraits do_traits() const override {
    sdk::PlannerTraits t;
    t.supports_2d = true;
    t.supports_3d = true;
    t.optimal = false;
    t.sampling = true;       // may miss a path within max_iterations
    t.deterministic = true;  // counted budgets, seeded per request (docs/planners.md §3)
    return t;
  }

 private:
  SamplingSettings settings_;
};

}  // namespace flipper::plugins::ompl

FLIPPER_PLUGIN(flipper::plugins::ompl::OmplPlanner, planner, "ompl", FLIPPER_PLUGIN_VERSION,
               "OMPL sampling planner (RRT-Connect, RRT, PRM, RRT*) with paths snapped to cells")
