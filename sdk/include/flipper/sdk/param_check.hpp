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
inline namespace FLIPPER_ABI_NAMESPACE {

/// Checks `given` against `schema` and returns the full parameter set (defaults filled in).
/// Checks: unknown keys (with a hint among the key's siblings and the list of them), type (an Int
/// is accepted for a Double), min/max, one_of, required (in an optional section: only when the
/// section is given; its defaults are then not filled either). `where` prefixes every key in
/// messages, e.g. "planner.params" ("" for the kernel's own keys). Every message names the full
/// key: "config key 'planner.params.weight' = 9.5 is out of range [0, 5]". Throws
/// Error(bad_config) on the first problem.
FLIPPER_SDK_API Params validate_params(const ParamSchema& schema,
                                       const std::map<std::string, ParamValue>& given,
                                       const std::string& where);

/// " (did you mean 'x'?)" for the closest candidate within a small edit distance (one edit per
/// three letters, a transposition counts one; never for a one-letter word; a two-letter word
/// keeps its first letter), else "".
FLIPPER_SDK_API std::string did_you_mean(const std::string& word,
                                         const std::vector<std::string>& candidates);

/// "bool", "int", "double", "string", "string list", "path", "path list", "double list", "map".
FLIPPER_SDK_API const char* to_string(ParamType type);

/// The type as messages say it: "an integer", "a list of strings", ...
FLIPPER_SDK_API const char* type_phrase(ParamType type);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
