#pragma once
// Equivalence of two executions (docs/naturalization.md §6): identical traces and final worlds, and
// neither raised an error. Returns why they differ, for the `define` answer.
#include <optional>
#include <string>

#include "flipper/sdk/execution.hpp"

namespace flipper::naturalization::generalize {

/// Nullopt when `candidate` is equivalent to `body`; else a reason such as
/// "different trace at step 3 (body: move to [3,4]; candidate: pick red circle at [2,4])",
/// "different final world: robot at [3,4] vs [4,4]" or "execution error: ...".
std::optional<std::string> difference(const sdk::Outcome& body, const sdk::Outcome& candidate);

}  // namespace flipper::naturalization::generalize
