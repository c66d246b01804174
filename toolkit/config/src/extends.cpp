// Reading a config file over the files it `extends` (docs/configuration.md), each a bounded
// YAML document without duplicate keys.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/regular_file.hpp"
#include "flipper/toolkit/config/yaml_bounds.hpp"
#include "yaml_tree.hpp"

namespace flipper::toolkit::config::detail {

namespace fs = std::filesystem;

namespace {

// yaml-cpp keeps both entries of a duplicated key and lookups see the first: a config that says
// `k: 3` twice would silently ignore one. Refused, naming the key and both lines.
void check_unique_keys(const YAML::Node& node, const std::string& source) {
  if (node.IsSequence())
    for (const auto& kid : node) check_unique_keys(kid, source);
  if (!node.IsMap()) return;
  std::map<std::string, int> seen;  // key -> line (1-based)
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    const int line = kv.first.Mark().line + 1;
    auto [it, fresh] = seen.emplace(key, line);
    if (!fresh)
      fail("config " + source + ":" + std::to_string(line) + ": duplicate key '" + key +
           "' (first at line " + std::to_string(it->second) + ")");
    check_unique_keys(kv.second, source);
  }
}

constexpr std::size_t kMaxExtendsDepth = 16;

// A config file is small: a regular file of at most yaml_bounds::kMaxConfigBytes (a fixed limit,
// since the config cannot set its own), so /dev/zero or a FIFO is an error, not a hang, and a
// huge document is refused before yaml-cpp reads it (about 75 MB of nodes per MiB of YAML).
std::string read_config_file(const std::string& path) {
  try {
    return read_regular_file(path, yaml_bounds::kMaxConfigBytes, "config file",
                             sdk::codes::kBadConfig);
  } catch (const sdk::Error& e) {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (std::string(e.code()) == sdk::codes::kFileTooLarge && !ec)
      fail("config file '" + path + "' has " + std::to_string(bytes) +
           " bytes; the limit for a config is " + std::to_string(yaml_bounds::kMaxConfigBytes) +
           " bytes (1 MiB)");
    fail(e.what());  // every config problem is bad_config (exit status 2)
  }
}

// Forgets the origins of `prefix` and every key below it (`prefix.*`, a contiguous range).
void erase_below(std::map<std::string, Origin>& origins, const std::string& prefix) {
  origins.erase(prefix);
  origins.erase(origins.lower_bound(prefix + "."), origins.lower_bound(prefix + "/"));
}

// Records `origin` for every leaf under `node` that has none yet (deeper bases recorded theirs).
void record_leaves(const YAML::Node& node, const std::string& prefix, const Origin& origin,
                   std::map<std::string, Origin>& origins) {
  if (node.IsMap()) {
    for (const auto& kv : node)
      record_leaves(kv.second,
                    prefix.empty() ? kv.first.Scalar() : prefix + "." + kv.first.Scalar(), origin,
                    origins);
    return;
  }
  if (!prefix.empty()) origins.emplace(prefix, origin);
}

// `overlay` over `base`, in place: maps merge key by key, anything else (scalars, lists, null)
// replaces. A plugin section whose `plugin` the overlay changes starts with no params: the base's
// params belong to the other plugin. Linear in the sizes of both: keys are found through an index
// (not yaml-cpp's linear lookup), and no subtree is copied (each copy re-registers every node of
// it with yaml-cpp's memory, once per level of nesting). `base` and `overlay` are both consumed:
// the result shares nodes with them.
YAML::Node merge(YAML::Node base, const YAML::Node& overlay, const std::string& prefix,
                 std::map<std::string, Origin>& origins, const DocumentRules& rules) {
  if (!base.IsMap() || !overlay.IsMap()) {
    erase_below(origins, prefix);
    return overlay;
  }
  const bool plugin_section = is_plugin_section(rules, prefix);
  const YAML::Node& read = base;  // const: yaml-cpp's operator[] would add an entry
  const bool other_plugin = plugin_section && overlay["plugin"].IsDefined() &&
                            read["plugin"].IsDefined() && overlay["plugin"].IsScalar() &&
                            read["plugin"].IsScalar() &&
                            overlay["plugin"].Scalar() != read["plugin"].Scalar();
  if (other_plugin) {
    erase_below(origins, prefix + ".params");
    base.remove("params");
  }
  std::unordered_map<std::string, YAML::Node> at;  // the base's values by key (first wins)
  for (const auto& kv : base) at.emplace(kv.first.Scalar(), kv.second);
  for (const auto& kv : overlay) {
    const std::string name = kv.first.Scalar();
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    if (auto it = at.find(name); it != at.end()) {
      // Assigning to the base's value node rewrites it where it stands (keeps the key's place).
      YAML::Node merged = merge(it->second, kv.second, key, origins, rules);
      if (!merged.is(it->second)) it->second = merged;
    } else {
      erase_below(origins, key);
      base.force_insert(kv.first, kv.second);
      at.emplace(name, kv.second);
    }
  }
  return base;
}

}  // namespace

YAML::Node parse_yaml(const std::string& text, const std::string& source) {
  try {
    YAML::Node root = YAML::Load(text);
    // Before anything walks the tree: an alias bomb loads at once and expands when walked.
    yaml_bounds::check_expanded_size(root, source);
    check_unique_keys(root, source);
    return root;
  } catch (const YAML::ParserException& e) {
    fail("config " + source + ":" + std::to_string(e.mark.line + 1) + ":" +
         std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
}

Layered load_layers(const std::string& file, const std::string& shown,
                    std::vector<std::string>& chain, const DocumentRules& rules) {
  YAML::Node root = parse_yaml(read_config_file(file), shown);
  if (!root.IsMap() || !root["extends"].IsDefined()) return {root, {}};
  const YAML::Node ext = root["extends"];
  if (!ext.IsScalar() || ext.Scalar().empty())
    fail("config " + shown + ": 'extends' must be the path of the config this one overlays, got " +
         scalar_text(ext));
  const fs::path dir = fs::absolute(file).lexically_normal().parent_path();
  const std::string base = resolve_against(dir.string(), ext.Scalar());
  std::error_code ec;
  if (!fs::exists(base, ec))
    fail("config " + shown + ": extends '" + ext.Scalar() + "', but there is no config at '" +
         base + "' (relative to its directory " + dir.string() + ")");
  const std::string id = fs::weakly_canonical(base, ec).string();
  if (std::find(chain.begin(), chain.end(), id) != chain.end()) {
    std::string cycle;
    for (const auto& c : chain) cycle += c + " -> ";
    fail("config " + shown + ": extends cycle: " + cycle + id);
  }
  if (chain.size() >= kMaxExtendsDepth)
    fail("config " + shown + ": more than " + std::to_string(kMaxExtendsDepth) +
         " configs extend one another");
  chain.push_back(id);
  Layered below = load_layers(base, base, chain, rules);
  chain.pop_back();
  record_leaves(below.root, "", {base, fs::path(base).parent_path().string()}, below.origins);
  root.remove("extends");
  below.root = merge(below.root, root, "", below.origins, rules);
  return below;
}

}  // namespace flipper::toolkit::config::detail
