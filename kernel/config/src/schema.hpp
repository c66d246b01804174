#pragma once
// The kernel's config schema: one table row per key (schema.cpp). Sections are implied by the
// dotted paths; a key of type Map is opaque here (plugin params, validated against the plugin's
// own schema by Config::plugin_params).
#include <string>
#include <string_view>
#include <vector>

namespace flipper::kernel::detail {

enum class KeyType { Bool, Int, Number, String, Path, StringList, PathList, NumberList, Map };

struct KeySpec {
  std::string path;  ///< dotted, e.g. "execution.action_budget"
  KeyType type;
  std::string default_yaml;  ///< YAML text of the default; empty: no default
  std::string rule;          ///< Int/Number: "min..max" (Number: exclusive min when it starts with
                             ///< ">"); String: "a|b|c" (enum); else empty
  bool required = false;     ///< must be given when its section is present
  bool optional_section = false;  ///< the section may be absent (no defaults filled then)
};

/// The table, in the order keys appear in the effective config.
const std::vector<KeySpec>& kernel_schema();
/// The row for an exact dotted path, or null.
const KeySpec* find_key(std::string_view path);
/// Whether some row lies below `prefix` (i.e. `prefix` names a section).
bool is_section(std::string_view prefix);
/// Names one level below `prefix` ("" for top level), for "did you mean" hints.
std::vector<std::string> child_names(std::string_view prefix);
const char* describe(KeyType type);

}  // namespace flipper::kernel::detail
