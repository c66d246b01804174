#pragma once
/// @file unrealizable.hpp (the session side: repair_extension.hpp)
/// Answers that repair a candidate that cannot be done in this world (docs/protocol.md
/// § "Repairs", docs/naturalization.md § 7): the smallest step of the program that fails, why it
/// fails in this world, and the nearest variant of the program that is realizable. Everything is
/// decided by the kernel's own executor (the same planner, world and limits as the query): the
/// step by executing the program's parts on the states they start from, the reason by executing
/// probe conditions (`if C {visit current}` runs one action exactly when C holds), the variant
/// by executing the whole edited program. The work is bounded by counts, never by wall time.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::naturalization {

/// Executions to find the failing step and say why, per candidate (the rest: `limited`).
inline constexpr std::size_t kMaxExplainRuns = 48;
/// Edited programs executed per candidate at most (the rest are not tried: `limited`).
inline constexpr std::size_t kMaxVariantRuns = 8;

/// A realizable program one edit away from the candidate's.
struct Variant {
  sdk::Program program;
  std::string edit;  ///< "replace 'red' by 'blue'", "drop 'is red'"
  int edits = 0;     ///< its tree distance: words replaced count 1, a dropped condition its nodes
};

struct Unrealizable {
  sdk::Program step;  ///< the smallest part that fails (the whole program if none smaller)
  sdk::Cell at;       ///< the robot's cell when that step ran
  std::string why;    ///< the reason, from the world ("no red item in room3")
  std::optional<Variant> variant;  ///< the nearest realizable variant (none found: empty)
  std::size_t tried = 0;           ///< edited programs executed
  std::string limited;             ///< why fewer were tried ("" when none was left out)
  std::size_t runs = 0;            ///< executions in all (step, reason and variants)
};

/// Runs a program on a world with the query's executor and limits.
using RunProgram =
    std::function<sdk::Outcome(const sdk::Program& program, const sdk::WorldState& world)>;

/// Whether this world decided that an execution failed, so that explain_unrealizable can say
/// why: not realizable, or an execution error (an unknown room); not a budget, a deadline or a
/// refused plugin.
bool decided_by_world(const sdk::Outcome& outcome);

/// Why `program`, whose execution `outcome` on `world` was not realizable, fails, and its
/// nearest realizable variant. `run` throws or returns deadline_exceeded like the executor;
/// an outcome with deadline_exceeded is thrown as sdk::StoppedError (the request's limit).
Unrealizable explain_unrealizable(const sdk::Program& program, const sdk::WorldState& world,
                                  const sdk::Outcome& outcome, const RunProgram& run);

}  // namespace flipper::naturalization
