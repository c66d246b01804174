#pragma once
/// @file executor.hpp
/// The executor of the core language (docs/core-language.md §4-§9): the only place that knows what
/// programs mean. Lenient by default; `strict` and `possible` run trials on scratch copies.
/// Uses a planner plugin for paths and tours; knows nothing of the world's kind of space.

#include <chrono>
#include <cstdint>
#include <memory>

#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::kernel {

struct ExecLimits {
  std::uint64_t action_budget = 100000;         ///< primitive actions per execution
  std::chrono::milliseconds time_budget{2000};  ///< wall time per execution
  int while_limit = 20;                         ///< iterations of `while`
};

class Executor : public sdk::ExecutionService {
 public:
  Executor(std::shared_ptr<const sdk::Planner> planner, ExecLimits limits = {});
  /// Runs `program` on a copy of `world`. Never throws for program/world problems: errors
  /// (unknown room, fractional count, budget exceeded) come back in Outcome::error, with
  /// Outcome::world equal to the start world.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override;
  /// The same within a request's deadline as well: execution stops at the earlier of
  /// execution.time_budget_ms and `deadline`; hitting `deadline` gives `deadline_exceeded`.
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world,
                   std::chrono::steady_clock::time_point deadline) const;
  const ExecLimits& limits() const { return limits_; }

 private:
  std::shared_ptr<const sdk::Planner> planner_;
  ExecLimits limits_;
};

}  // namespace flipper::kernel
