#pragma once
/// @file executor.hpp
/// The executor of the core language (docs/core-language.md §4-§9): the only place that knows what
/// programs mean. Lenient by default; `strict` and `possible` run trials on scratch copies.
/// Uses a planner plugin for paths and tours; knows nothing of the world's kind of space.

#include <chrono>
#include <cstdint>
#include <memory>

#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::kernel {

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

class Executor : public sdk::ExecutionService {
 public:
  /// Every planner call goes through `planner` (a bare shared_ptr converts, named "in-process").
  Executor(PluginRef<const sdk::Planner> planner, ExecLimits limits = {});
  /// Runs `program` on a copy of `world`. Never throws: errors (unknown room, fractional count,
  /// budget_exceeded, deadline_exceeded, a failing planner: plugin_error naming it) come back
  /// in Outcome::error, with Outcome::world equal to the start world.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override;
  /// The same within a request's limits as well: execution stops when either its own limits
  /// (execution.cpu_budget_ms, execution.deadline_ms) or the request's (`request`: its CPU
  /// budget, wall backstop and cancel flag) fire, with `deadline_exceeded` naming the one.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world,
                   const sdk::StopCondition& request) const;
  const ExecLimits& limits() const { return limits_; }

 private:
  PluginRef<const sdk::Planner> planner_;
  ExecLimits limits_;
};

}  // namespace flipper::kernel
