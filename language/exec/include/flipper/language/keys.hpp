#pragma once
/// @file keys.hpp
/// The core language's config keys, the section `execution` (docs/config.md "Who declares a
/// key"): the limits of one program's execution, each one typed handle of the SDK. ExecLimits
/// takes its defaults from them. The kernel, which runs the executions of its sessions, puts this
/// section into its schema fragment where it always stood (after `grammar`).

#include <cstdint>

#include "flipper/sdk/config_handles.hpp"

namespace flipper::language::keys {

using Int = sdk::param::Int<std::int64_t>;

// Time limits (docs/planners.md §2): work and CPU time decide; the wall clock only ends runaways.
inline constexpr Int kActionBudget{"execution.action_budget", 100000, 1, 1000000000000,
                                   "primitive actions one program may take (work: then "
                                   "budget_exceeded)"};
inline constexpr Int kStepBudget{"execution.step_budget", 1000000, 1, 1000000000000,
                                 "statements one program may execute, loop iterations and "
                                 "trial runs included (work: then budget_exceeded)"};
inline constexpr Int kExecCpuBudgetMs{"execution.cpu_budget_ms", 2000, 1, 86400000,
                                      "CPU time of one execution on the request thread: then "
                                      "deadline_exceeded, stopped: cpu_budget (never a different "
                                      "plan)"};
inline constexpr Int kExecDeadlineMs{"execution.deadline_ms", 300000, 1, 86400000,
                                     "wall-clock backstop of one execution, against hangs (not "
                                     "load): then deadline_exceeded, stopped: wall_backstop"};
inline constexpr Int kWhileLimit{"execution.while_limit", 20, 0, 1000000,
                                 "iterations of one `while`"};

/// Appends the section `execution` to `schema`.
inline void add_config(sdk::ParamSchema& schema) {
  schema.add_section("execution", "limits of one program's execution");
  sdk::param::add(schema, kActionBudget);
  sdk::param::add(schema, kStepBudget);
  sdk::param::add(schema, kWhileLimit);
  sdk::param::add(schema, kExecCpuBudgetMs);
  sdk::param::add(schema, kExecDeadlineMs);
  schema.add_retired("execution.time_budget_ms",
                     "it was a wall-clock budget, so a result depended on the machine's load; "
                     "results are bounded by work now (execution.action_budget, "
                     "execution.step_budget) and by CPU time (execution.cpu_budget_ms), and the "
                     "wall-clock limit is the far backstop execution.deadline_ms; either refuses "
                     "the query (deadline_exceeded) instead of changing a plan "
                     "(docs/planners.md §2)");
}

}  // namespace flipper::language::keys
