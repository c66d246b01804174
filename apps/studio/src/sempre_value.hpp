#pragma once
// A /sempre candidate's `value` (docs/sempre.md § "Values"): the JSON text
//   {"status": "<warning or empty>", "path": [[x, y, action, color, shape, possible], ...]}
// with action path | destination | pickitem | dropitem, the original's form of an execution,
// built from Flipper's trace (core-language §5 relates the two). The path starts at the robot's
// cell: the first movement begins with a `path` entry for the cell it leaves.
#include <string>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::studio {

/// `whole` is `program` executed on `start`. The statements of a sequence and the iterations of
/// a `repeat` with a literal count are executed again one by one with `exec` (same world, same
/// results: the executor is deterministic), so that each movement ends in a `destination`,
/// visiting the robot's own cell gives one `destination`, and a failed pick or drop gives its
/// entry with possible = false, as in the original. Within another compound statement (`foreach`,
/// `if`, `while`, `strict`) a movement ends where the robot next picks, drops or stops, and each
/// step of a statement made only of `move`s is its own movement. An execution error gives a value
/// that is not of that shape (the client shows it as an error and offers no accept), as the
/// original's failed executions did.
std::string sempre_value(const sdk::Program& program, const sdk::WorldState& start,
                         const sdk::Outcome& whole, const sdk::ExecutionService& exec);

}  // namespace flipper::studio
