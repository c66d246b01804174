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

/// execution.*; defaults from keys.hpp (one place). The budgets count work, so whether a program
/// exceeds one never depends on the machine (docs/core-language.md §9); the deadline only stops
/// runaways, and then the execution fails with deadline_exceeded instead of giving a plan.
struct ExecLimits {
  std::uint64_t action_budget = static_cast<std::uint64_t>(keys::kActionBudget.def);
  std::uint64_t step_budget = static_cast<std::uint64_t>(keys::kStepBudget.def);  ///< statements
  int while_limit = static_cast<int>(keys::kWhileLimit.def);      ///< iterations of `while`
  std::chrono::milliseconds deadline{keys::kExecDeadlineMs.def};  ///< runaway deadline
};

class Executor : public sdk::ExecutionService {
 public:
  /// Every planner call goes through `planner` (a bare shared_ptr converts, named "in-process").
  Executor(PluginRef<const sdk::Planner> planner, ExecLimits limits = {});
  /// Runs `program` on a copy of `world`. Never throws: errors (unknown room, fractional count,
  /// budget_exceeded, deadline_exceeded, a failing planner: plugin_error naming it) come back
  /// in Outcome::error, with Outcome::world equal to the start world.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override;
  /// The same within a request's deadline as well: execution stops at the earlier of
  /// execution.deadline_ms and `deadline`, with `deadline_exceeded` naming the one that fired.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world,
                   std::chrono::steady_clock::time_point deadline) const;
  const ExecLimits& limits() const { return limits_; }

 private:
  PluginRef<const sdk::Planner> planner_;
  ExecLimits limits_;
};

}  // namespace flipper::kernel
