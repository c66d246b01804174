#pragma once
// Bounds on a config document before anything walks it (docs/bad-input.md): its size in bytes,
// and its size in YAML nodes with every alias counted as the nodes it repeats. yaml-cpp keeps an
// alias as a second handle on the node it names, so a few hundred bytes of aliases to aliases
// (a "billion laughs" document) load at once but expand to billions of nodes for any code that
// walks the tree.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>

namespace flipper::toolkit::config::yaml_bounds {

/// A config file has at most this many bytes (1 MiB; the configs in configs/ have under 5 KiB).
inline constexpr std::uint64_t kMaxConfigBytes = std::uint64_t{1} << 20;
/// A config document has at most this many nodes, aliases expanded (keys, values and list
/// elements each count one).
inline constexpr std::size_t kMaxConfigNodes = 100000;

/// Throws bad_config naming `source` and the limit when `root` expands to more than
/// kMaxConfigNodes nodes. Visits at most kMaxConfigNodes + 1 nodes (no recursion).
void check_expanded_size(const YAML::Node& root, const std::string& source);

/// A map with the null values of `node` left out, at every level below (others as they are).
/// Linear in the size of the tree: entries are appended, not looked up (the keys of a config
/// are unique: parse_yaml refused duplicates).
YAML::Node without_nulls(const YAML::Node& node);

}  // namespace flipper::toolkit::config::yaml_bounds
