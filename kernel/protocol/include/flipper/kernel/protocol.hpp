#pragma once
/// @file protocol.hpp
/// docs/protocol.md's trace of an execution result as compact text, shared by the session's
/// answers (`query`, `accept`): steps `{"act":"move","to":P}` /
/// `{"act":"pick"|"drop","at":P,"item":ITEM}` (core-language §5), cells `[x, y]` / `[x, y, z]`.
/// The JSON trees of the same shapes, which only the terminal front ends build, are theirs
/// (flipper/repl/outcome_json.hpp).

#include <string>
#include <vector>

#include "flipper/sdk/execution.hpp"

namespace flipper::kernel::protocol {

/// Appends the trace as compact JSON text, exactly as nlohmann's dump writes its tree (invalid
/// UTF-8 replaced), without building the tree: long traces are most of a big answer.
void append_trace_text(std::string& out, const std::vector<sdk::TraceStep>& trace, int dims);

}  // namespace flipper::kernel::protocol
