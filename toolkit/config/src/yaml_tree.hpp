#pragma once
// What the parts of a config document share (document.cpp, extends.cpp, overrides.cpp,
// typed_values.cpp): dotted keys in a YAML tree, and the one error of a bad document.
#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "flipper/toolkit/config/document.hpp"
#include "flipper/toolkit/config/typed_values.hpp"

namespace flipper::toolkit::config::detail {

/// Throws sdk::Error(bad_config, message).
[[noreturn]] void fail(const std::string& message);

/// "a.b.c" -> {"a", "b", "c"}.
std::vector<std::string> split_key(const std::string& key);
/// The node at the key `segs` below `node`, without creating anything (yaml-cpp's Node
/// assignment aliases, so navigation is by recursion over fresh handles).
std::optional<YAML::Node> lookup(const YAML::Node& node, const std::vector<std::string>& segs,
                                 std::size_t i = 0);
/// Sets the key `segs` (from index `i`) below `node` to `value`, making maps on the way.
void set_path(YAML::Node node, const std::vector<std::string>& segs, std::size_t i,
              const YAML::Node& value);
/// Whether `section` is one of the rules' plugin sections.
bool is_plugin_section(const DocumentRules& rules, const std::string& section);

/// The tree of a file with the origins of the keys that came from the files it extends.
struct Layered {
  YAML::Node root;
  std::map<std::string, Origin> origins;
};
/// Parses a document (`source` names it in messages): bounded, no duplicate keys.
YAML::Node parse_yaml(const std::string& text, const std::string& source);
/// Reads `file` (named `shown` in messages) over the chain of files it extends. `chain` holds the
/// canonical paths being read, to refuse cycles.
Layered load_layers(const std::string& file, const std::string& shown,
                    std::vector<std::string>& chain, const DocumentRules& rules);
/// Applies one --set to `root`, recording its key in `cli_keys`.
void apply_assignment(YAML::Node& root, const std::string& assignment,
                      std::set<std::string>& cli_keys, const DocumentRules& rules);

}  // namespace flipper::toolkit::config::detail
