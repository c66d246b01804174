#include "serial_prm.hpp"

#include <vector>

#include <ompl/base/goals/GoalSampleableRegion.h>

namespace flipper::plugins::ompl {
namespace ob = ::ompl::base;

namespace {
// Termination-condition checks per slice: growing gets twice the share of expanding, as in
// OMPL's PRM (which times them 2:1). A growing step checks about twice per sample.
constexpr unsigned kGrowSlice = 64;
constexpr unsigned kExpandSlice = 32;
constexpr std::size_t kBounceSteps = 5;  // OMPL's PRM: MAX_RANDOM_BOUNCE_STEPS
}  // namespace

SerialPrm::SerialPrm(const ob::SpaceInformationPtr& si) : ::ompl::geometric::PRM(si) {
  setName("PRM (serial, counted)");
}

ob::PlannerStatus SerialPrm::solve(const ob::PlannerTerminationCondition& ptc) {
  checkValidity();
  auto* goal = dynamic_cast<ob::GoalSampleableRegion*>(pdef_->getGoal().get());
  if (goal == nullptr) return ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE;
  while (const ob::State* st = pis_.nextStart())
    startM_.push_back(addMilestone(si_->cloneState(st)));
  if (startM_.empty()) return ob::PlannerStatus::INVALID_START;
  if (goalM_.empty()) {
    if (const ob::State* st = pis_.nextGoal(ptc))
      goalM_.push_back(addMilestone(si_->cloneState(st)));
  }
  if (goalM_.empty()) return ob::PlannerStatus::INVALID_GOAL;
  if (!sampler_) sampler_ = si_->allocValidStateSampler();
  if (!simpleSampler_) simpleSampler_ = si_->allocStateSampler();

  std::vector<ob::State*> work(kBounceSteps);
  si_->allocStates(work);
  ob::PathPtr solution;
  bool grow = true;
  // The start and goal milestones may already be connected (a free straight line).
  while (!maybeConstructSolution(startM_, goalM_, solution) && !ptc) {
    ob::IterationTerminationCondition slice(grow ? kGrowSlice : kExpandSlice);
    const ob::PlannerTerminationCondition bounded = ob::plannerOrTerminationCondition(ptc, slice);
    if (grow)
      growRoadmap(bounded, work[0]);
    else
      expandRoadmap(bounded, work);
    grow = !grow;
  }
  si_->freeStates(work);
  if (!solution) return ob::PlannerStatus::TIMEOUT;
  ob::PlannerSolution found(solution);
  found.setPlannerName(getName());
  pdef_->addSolutionPath(found);
  return ob::PlannerStatus::EXACT_SOLUTION;
}

}  // namespace flipper::plugins::ompl
