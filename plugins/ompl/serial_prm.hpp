#pragma once
// PRM on one thread with counted slices (docs/planners.md §3). OMPL's own PRM::solve grows and
// expands its roadmap in wall-clock slices (0.2 s / 0.1 s) while a second thread looks for a
// start-goal connection every millisecond, so where it stops depends on the machine's load.
// This solve does the same steps in a fixed order: grow the roadmap for a counted slice, look
// for a solution, expand it for a counted slice, look again, ... until the caller's termination
// condition (counted too) fires. Roadmap, connection strategy and solution search are OMPL's.
#include <ompl/geometric/planners/prm/PRM.h>
// OMPL 1.5's IterationTerminationCondition.h has no include guard: included here, once, for this
// plugin's units that count iterations (serial_prm.cpp, sampling.cpp), which compile as one batch
// (the product's unity build, CMakeLists.txt FLIPPER_UNITY).
#include <ompl/base/terminationconditions/IterationTerminationCondition.h>

namespace flipper::plugins::ompl {

class SerialPrm final : public ::ompl::geometric::PRM {
 public:
  explicit SerialPrm(const ::ompl::base::SpaceInformationPtr& si);

  ::ompl::base::PlannerStatus solve(const ::ompl::base::PlannerTerminationCondition& ptc) override;
};

}  // namespace flipper::plugins::ompl
