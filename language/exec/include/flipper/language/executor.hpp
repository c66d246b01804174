#pragma once
/// @file executor.hpp
/// The executor of the core language (docs/core-language.md §4-§9): the only place that knows what
/// programs mean. Lenient by default; `strict` and `possible` run trials on scratch copies.
/// Paths and tours come from a planner it reaches only through PlannerAccess; it knows nothing of
/// the world's kind of space, nor of plugins: the kernel gives it a planner whose answers it has
/// checked (kernel::Executor, docs/plugins-untrusted.md).

#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "flipper/language/keys.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::language {

/// execution.*; defaults from keys.hpp (one place). The budgets count work or the request thread's
/// CPU time, so whether a program exceeds one does not depend on the machine's load
/// (docs/core-language.md §9, docs/planners.md §2); the wall-clock deadline is a far backstop
/// against hangs. Either makes the execution fail with deadline_exceeded (Outcome::stopped says
/// which) instead of giving a plan.
struct ExecLimits {
  std::uint64_t action_budget = static_cast<std::uint64_t>(keys::kActionBudget.def);
  std::uint64_t step_budget = static_cast<std::uint64_t>(keys::kStepBudget.def);  ///< statements
  int while_limit = static_cast<int>(keys::kWhileLimit.def);         ///< iterations of `while`
  std::chrono::milliseconds cpu_budget{keys::kExecCpuBudgetMs.def};  ///< CPU time
  std::chrono::milliseconds deadline{keys::kExecDeadlineMs.def};     ///< wall-clock backstop
};

/// The planner as the executor sees it: a path or tour answer it may act on (checked by whoever
/// implements this), and the planner's traits. Calls come on the execution's thread, one at a
/// time. `stop` is the execution's own stop condition: an implementation whose work runs off this
/// thread (a child process) charges that CPU time to it, so budgets keep counting work.
class PlannerAccess {
 public:
  virtual ~PlannerAccess() = default;
  virtual sdk::PlannerTraits traits() const = 0;
  virtual sdk::PathResult plan(const sdk::Geometry& geometry, const sdk::PathRequest& request,
                               sdk::StopCondition& stop) const = 0;
  virtual sdk::TourResult tour(const sdk::Geometry& geometry, sdk::Cell start,
                               const std::vector<sdk::Cell>& points,
                               sdk::StopCondition& stop) const = 0;
};

class Executor : public sdk::ExecutionService {
 public:
  /// Every planner call goes through `planner` (not null).
  explicit Executor(std::shared_ptr<const PlannerAccess> planner, ExecLimits limits = {});
  /// Runs `program` on a copy of `world`. Never throws: errors (unknown room, fractional count,
  /// budget_exceeded, deadline_exceeded, a failing planner: the error it threw) come back in
  /// Outcome::error, with Outcome::world equal to the start world.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override;
  /// The same within a request's limits as well: execution stops when either its own limits
  /// (execution.cpu_budget_ms, execution.deadline_ms) or the request's (`request`: its CPU
  /// budget, wall backstop and cancel flag) fire, with `deadline_exceeded` naming the one.
  /// The one-argument run is this one without a request's limits; a subclass may change where
  /// the planner's calls run (kernel::Executor), never what they mean.
  virtual sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world,
                           const sdk::StopCondition& request) const;
  const ExecLimits& limits() const { return limits_; }

 private:
  std::shared_ptr<const PlannerAccess> planner_;
  ExecLimits limits_;
};

}  // namespace flipper::language
