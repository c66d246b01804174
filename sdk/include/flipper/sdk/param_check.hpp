#pragma once
/// @file param_check.hpp
/// The one validation of plugin parameters against a declared ParamSchema, shared by the kernel
/// (after it has read the YAML config) and by the conformance kit (which has no YAML). Strict on
/// purpose: an unknown key is an error with a "did you mean" hint, never silently ignored.

#include <map>
#include <string>
#include <vector>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/params.hpp"

namespace flipper::sdk {
inline namespace v1 {

/// Checks `given` against `schema` and returns the full parameter set (defaults filled in).
/// Checks: unknown keys (with a hint), type (an Int is accepted for a Double), min/max, one_of,
/// required. `where` prefixes every message with the config key path, e.g. "planner.params".
/// Throws Error(bad_config) on the first problem.
FLIPPER_SDK_API Params validate_params(const ParamSchema& schema,
                                       const std::map<std::string, ParamValue>& given,
                                       const std::string& where);

/// " (did you mean 'x'?)" for the closest candidate within a small edit distance, else "".
FLIPPER_SDK_API std::string did_you_mean(const std::string& word,
                                         const std::vector<std::string>& candidates);

/// "bool", "int", "double", "string", "string list", "path".
FLIPPER_SDK_API const char* to_string(ParamType type);

}  // namespace v1
}  // namespace flipper::sdk
