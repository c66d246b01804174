#pragma once
/// @file measure.hpp
/// One benchmark cell (a world, a planner with its seed) over its tasks: each plan's outcome
/// checked against the oracle, and what it cost (docs/planners.md §5). Deterministic columns:
/// status, success, length, turns, expansions. Measured ones: plan CPU time (the calling
/// thread's, not wall time), wall time, and the peak resident memory during the plan.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/planbench/tasks.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::planbench {

/// The columns of runs.csv, in order.
const std::vector<std::string>& run_columns();
/// The columns whose values are measured (may differ between runs of the same inputs).
bool is_measured_column(const std::string& column);

struct RunRow {
  std::string world, planner, plugin, seed, task, start, goal;
  /// found | no_path | stopped | invalid (the planner's), or `varies` (repetitions gave
  /// different answers), or the error code of a plan call that threw (`plugin_error`) or whose
  /// answer the kernel refused (`invalid_plan`: not a path of free neighbouring cells from the
  /// start to the goal, docs/plugins-untrusted.md); the run goes on with the next task.
  std::string status;
  /// With status `stopped`: the limit that fired, `cpu_budget` or `wall_backstop` (or
  /// `cancelled`); empty otherwise (docs/planners.md §5).
  std::string stopped;
  bool success = false;  ///< a valid path to a reachable goal, or no_path for an unreachable one
  std::optional<std::size_t> length, shortest;           ///< steps
  std::size_t turns = 0;                                 ///< changes of direction along the path
  std::uint64_t expansions = 0;                          ///< the planner's own count of work
  double cpu_us = 0, wall_us = 0;                        ///< median over the repetitions
  std::optional<std::int64_t> peak_rss_kib, memory_kib;  ///< VmHWM during the plan, and its growth
  /// Why a task has no answer when its process died (status `plugin_crashed` or `crashed`: the
  /// signal, "SIGSEGV"; `wall_backstop`: "killed after N s"; `failed`: the error), else "".
  std::string cause;
};

/// The row as CSV fields (runs.csv's columns).
std::vector<std::string> row_fields(const RunRow& row);

/// Changes of direction along start, path[0], path[1], ...
std::size_t count_turns(sdk::Cell start, const std::vector<sdk::Cell>& path);

struct CellSpec {
  std::string world, planner, plugin, seed;
  int repetitions = 1;
  std::int64_t deadline_ms = 600000;   ///< wall-clock backstop of one plan
  std::int64_t cpu_budget_ms = 10000;  ///< CPU time of one plan on the planning thread
};

/// Plans every task with `planner` on `g`, in order.
std::vector<RunRow> measure_cell(const CellSpec& cell, const sdk::Geometry& g,
                                 const kernel::PluginRef<sdk::Planner>& planner,
                                 const std::vector<Task>& tasks);

}  // namespace flipper::planbench
