#pragma once
/// @file typed_values.hpp
/// A config document's maps as the typed values of an sdk::ParamSchema (for the SDK's one
/// validation engine, sdk::validate_params), and validated values back as YAML. A value of the
/// wrong shape is sdk::Error(bad_config), worded as the engine words its own type errors.

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "flipper/sdk/params.hpp"

namespace flipper::toolkit::config {

/// Resolves the text of a Path value written at `key` (or returns it as written).
using PathFn = std::function<std::string(const std::string& key, const std::string& text)>;

/// The map `node` as the dotted names sdk::validate_params takes: declared keys typed (Path and
/// PathList values through `path`), sections descended, an unknown key passed on as is (the
/// engine names it, with a hint among its siblings). `where` prefixes the keys in messages
/// ("planner.params").
std::map<std::string, sdk::ParamValue> typed_values(const YAML::Node& node,
                                                    const sdk::ParamSchema& schema,
                                                    const std::string& where, const PathFn& path);

/// The schema's keys that `values` holds, in schema order, as YAML text: each value in its type's
/// one spelling (`off` -> false, `1.0` -> 1), a Map key as `tree` has it (e.g. a plugin's params).
std::string dump_values(const sdk::ParamSchema& schema, const sdk::Params& values,
                        const YAML::Node& tree);

/// Throws "config key 'KEY' must be TYPE, got VALUE" (bad_config).
[[noreturn]] void wrong_type(const std::string& key, sdk::ParamType type, const YAML::Node& v);
/// A value as messages quote it: 'text', a list, a map, null.
std::string scalar_text(const YAML::Node& n);
/// The integer a scalar spells, if it spells one exactly.
std::optional<std::int64_t> parse_int(const std::string& s);

}  // namespace flipper::toolkit::config
