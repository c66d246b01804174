#include "sampling.hpp"

#include <cmath>
#include <limits>
#include <mutex>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRT.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/RandomNumbers.h>

#include "serial_prm.hpp"

namespace flipper::plugins::ompl {
namespace ob = ::ompl::base;
namespace og = ::ompl::geometric;
using sdk::Cell;

namespace {

// Validity in cell units: the point rounds to a passable cell (free, not avoided, or the start)
// and, if the world has a continuous view, the body fits there.
struct Validity {
  const CellSearch& search;
  const sdk::ContinuousSpace* space;
  int dims;

  void read(const ob::State* s, double p[3]) const {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    p[0] = v->values[0];
    p[1] = v->values[1];
    p[2] = dims == 3 ? v->values[2] : 0.0;
  }
  bool cell_ok(const double p[3]) const {
    return search.passable({static_cast<std::int32_t>(std::lround(p[0])),
                            static_cast<std::int32_t>(std::lround(p[1])),
                            static_cast<std::int32_t>(std::lround(p[2]))});
  }
  bool state(const double p[3]) const {
    return cell_ok(p) && (space == nullptr || space->is_state_valid(p));
  }
  // Valid fraction of a->b: 1 if all of it is valid, else the last valid sub-step (< 1).
  double motion(const double a[3], const double b[3]) const {
    const double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.25)));  // <= 1/4 cell
    for (int i = 1; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const double p[3] = {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
      if (!cell_ok(p)) return static_cast<double>(i - 1) / steps;
    }
    if (space != nullptr && !space->is_motion_valid(a, b)) {
      for (int i = 1; i <= steps; ++i) {  // rare: locate the first colliding sub-step
        const double t = static_cast<double>(i) / steps;
        const double p[3] = {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
        if (!space->is_state_valid(p)) return static_cast<double>(i - 1) / steps;
      }
      return 0.0;
    }
    return 1.0;
  }
};

class SubstepMotionValidator final : public ob::MotionValidator {
 public:
  SubstepMotionValidator(ob::SpaceInformation* si, const Validity& validity)
      : ob::MotionValidator(si), validity_(validity) {}

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    double a[3], b[3];
    validity_.read(s1, a);
    validity_.read(s2, b);
    const bool ok = validity_.state(b) && validity_.motion(a, b) >= 1.0;
    ok ? ++valid_ : ++invalid_;
    return ok;
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2,
                   std::pair<ob::State*, double>& last_valid) const override {
    double a[3], b[3];
    validity_.read(s1, a);
    validity_.read(s2, b);
    const double f = validity_.motion(a, b);
    if (f >= 1.0 && validity_.state(b)) {
      ++valid_;
      return true;
    }
    const double t = std::min(f, 1.0 - 1e-9);
    if (last_valid.first != nullptr) si_->getStateSpace()->interpolate(s1, s2, t, last_valid.first);
    last_valid.second = t;
    ++invalid_;
    return false;
  }

 private:
  Validity validity_;
};

// OMPL draws the seed of every random generator it creates (samplers, planners, nearest-neighbour
// structures, the path simplifier) from one process-wide seed generator. Reseeding it right
// before the objects of a request are built makes the request reproducible; the lock keeps two
// concurrent requests from interleaving their draws.
std::mutex& seed_mutex() {
  static std::mutex m;
  return m;
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

ob::PlannerPtr make_planner(const ob::SpaceInformationPtr& si, const SamplingSettings& s) {
  switch (s.algorithm) {
    case Algorithm::rrt: {
      auto p = std::make_shared<og::RRT>(si);
      if (s.range > 0) p->setRange(s.range);
      return p;
    }
    case Algorithm::prm:
      return std::make_shared<SerialPrm>(si);
    case Algorithm::rrtstar: {
      auto p = std::make_shared<og::RRTstar>(si);
      if (s.range > 0) p->setRange(s.range);
      return p;
    }
    case Algorithm::rrtconnect:
    default: {
      auto p = std::make_shared<og::RRTConnect>(si);
      if (s.range > 0) p->setRange(s.range);
      return p;
    }
  }
}

}  // namespace

std::uint32_t request_seed(std::uint32_t seed, Cell start, Cell goal) {
  std::uint64_t h = splitmix64(seed);
  for (const std::int32_t v : {start.x, start.y, start.z, goal.x, goal.y, goal.z})
    h = splitmix64(h ^ static_cast<std::uint32_t>(v));
  const auto folded = static_cast<std::uint32_t>(h ^ (h >> 32));
  return folded == 0 ? 1 : folded;
}

const char* algorithm_name(Algorithm a) {
  switch (a) {
    case Algorithm::rrt:
      return "rrt";
    case Algorithm::prm:
      return "prm";
    case Algorithm::rrtstar:
      return "rrtstar";
    case Algorithm::rrtconnect:
    default:
      return "rrtconnect";
  }
}

SamplingOutcome sample_path(const CellSearch& search, Cell goal, const SamplingSettings& settings,
                            const sdk::StopCondition& stop) {
  const sdk::Geometry& g = search.geometry();
  const int dims = g.dims();
  const std::lock_guard<std::mutex> lock(seed_mutex());
  ::ompl::RNG::setSeed(request_seed(settings.seed, search.start(), goal));

  auto space = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned>(dims));
  ob::RealVectorBounds bounds(static_cast<unsigned>(dims));
  const Cell lo = g.min(), hi = g.max();
  const double l[3] = {double(lo.x), double(lo.y), double(lo.z)};
  const double h[3] = {double(hi.x), double(hi.y), double(hi.z)};
  for (int i = 0; i < dims; ++i) {  // +-0.49: every sample still rounds to a cell of the box
    bounds.setLow(static_cast<unsigned>(i), l[i] - 0.49);
    bounds.setHigh(static_cast<unsigned>(i), h[i] + 0.49);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  const Validity validity{search, g.continuous(), dims};
  si->setStateValidityChecker([validity](const ob::State* s) {
    double p[3];
    validity.read(s, p);
    return validity.state(p);
  });
  si->setMotionValidator(std::make_shared<SubstepMotionValidator>(si.get(), validity));
  si->setup();

  ob::ScopedState<> start(space), target(space);
  const Cell s = search.start();
  const double sc[3] = {double(s.x), double(s.y), double(s.z)};
  const double gc[3] = {double(goal.x), double(goal.y), double(goal.z)};
  for (int i = 0; i < dims; ++i) {
    start[static_cast<unsigned>(i)] = sc[i];
    target[static_cast<unsigned>(i)] = gc[i];
  }
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(start, target, 1e-6);
  auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
  if (settings.algorithm == Algorithm::prm)  // stop at the first roadmap solution
    objective->setCostThreshold(ob::Cost(std::numeric_limits<double>::infinity()));
  pdef->setOptimizationObjective(objective);

  ob::PlannerPtr planner = make_planner(si, settings);
  planner->setProblemDefinition(pdef);
  planner->setup();

  // Stops on the caller's condition (expansion budget counted in checks; its CPU budget, wall
  // backstop and cancel flag every 64 checks: reading the CPU clock is a syscall) and
  // on the own budget of max_iterations checks, both counted on this one thread; RRT* is anytime
  // and, after its first solution, refines for `iterations` more checks (counted too).
  ob::IterationTerminationCondition budget(settings.max_iterations);
  std::uint64_t first_solution_at = 0;
  bool caller_stopped = false;
  const bool refine = settings.algorithm == Algorithm::rrtstar && settings.iterations > 0;
  if (refine)
    pdef->setIntermediateSolutionCallback(
        [&](const ob::Planner*, const std::vector<const ob::State*>&, const ob::Cost&) {
          if (first_solution_at == 0) first_solution_at = budget.getTimesCalled();
        });
  const ob::PlannerTerminationCondition ptc([&] {
    if (budget.eval()) return true;
    const std::uint64_t n = budget.getTimesCalled();
    if (n >= stop.max_expansions || ((n & 63u) == 0 && stop.expired()))
      return caller_stopped = true;
    return refine && first_solution_at > 0 && n - first_solution_at >= settings.iterations;
  });
  planner->solve(ptc);

  SamplingOutcome out;
  out.iterations = budget.getTimesCalled();
  if (!pdef->hasExactSolution()) {
    if (caller_stopped) {
      out.status = sdk::PlanStatus::stopped;
      out.message = "stopped before a path was found";
    } else {
      out.status = sdk::PlanStatus::no_path;
      out.message = std::string("no path found by ") + algorithm_name(settings.algorithm) +
                    " within max_iterations = " + std::to_string(settings.max_iterations);
    }
    return out;
  }
  auto& path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  if (settings.simplify) {
    og::PathSimplifier simplifier(si);
    simplifier.reduceVertices(path);
    simplifier.shortcutPath(path);
  }
  for (const ob::State* st : path.getStates()) {
    double p[3];
    validity.read(st, p);
    out.waypoints.push_back({p[0], p[1], p[2]});
  }
  out.status = sdk::PlanStatus::found;
  return out;
}

}  // namespace flipper::plugins::ompl
