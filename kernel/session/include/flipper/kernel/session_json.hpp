#pragma once
/// @file session_json.hpp
/// Protocol JSON for execution results (core-language.md §5): points, items, trace steps.

#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/sdk/execution.hpp"

namespace flipper::kernel::protocol_json {

/// [x, y] or [x, y, z].
Json point(const sdk::Cell& c, int dims);
/// {"id", "color", "shape"}.
Json item(const sdk::ItemInfo& item);
/// [{"act":"move","to":[x,y]}, {"act":"pick","at":[x,y],"item":{...}}, ...].
Json trace(const std::vector<sdk::TraceStep>& steps, int dims);
Json strings(const std::vector<std::string>& values);

}  // namespace flipper::kernel::protocol_json
