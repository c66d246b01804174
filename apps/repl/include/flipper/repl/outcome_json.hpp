#pragma once
/// @file outcome_json.hpp
/// JSON trees of docs/protocol.md's shapes for execution results, for the terminal front ends
/// (`flipper run --json`, the REPL's views): cells `[x, y]` / `[x, y, z]`, items
/// `{"id","color","shape"}`, trace steps `{"act":"move","to":P}` /
/// `{"act":"pick"|"drop","at":P,"item":ITEM}` (core-language §5), errors `{"code","message"}`,
/// and an outcome's pieces. The session writes the same shapes as text, without a tree
/// (kernel/protocol `append_trace_text`, the answer writer).

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/execution.hpp"

namespace flipper::repl {

using Json = nlohmann::json;

/// [x, y] (dims 2) or [x, y, z] (dims 3).
Json cell_json(const sdk::Cell& c, int dims);
/// {"id", "color", "shape"}.
Json item_json(const sdk::ItemInfo& item);
Json step_json(const sdk::TraceStep& step, int dims);
Json trace_json(const std::vector<sdk::TraceStep>& trace, int dims);
Json strings_json(const std::vector<std::string>& values);
/// {"code", "message"}.
Json error_json(const std::string& code, const std::string& message);
Json error_json(const sdk::Error& error);

/// The execution part of a candidate or an `accept` answer: {"trace", "warnings", "realizable"}
/// and, for an erroneous execution, "error": {"code","message"}. The world is added by the
/// caller (it needs the world plugin's `save`).
Json outcome_json(const sdk::Outcome& outcome, int dims);

}  // namespace flipper::repl
