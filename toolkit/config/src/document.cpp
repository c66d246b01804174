// A config document: the layered tree, who wrote each key, and paths relative to the writer.
#include "flipper/toolkit/config/document.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <unordered_set>
#include <utility>

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/yaml_bounds.hpp"
#include "yaml_tree.hpp"

namespace flipper::toolkit::config {

namespace fs = std::filesystem;

namespace detail {

void fail(const std::string& message) {
  throw sdk::Error(sdk::codes::kBadConfig, message);
}

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    out.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return out;
}

std::optional<YAML::Node> lookup(const YAML::Node& node, const std::vector<std::string>& segs,
                                 std::size_t i) {
  if (i == segs.size()) return node;
  if (!node.IsMap()) return std::nullopt;
  const YAML::Node child = node[segs[i]];
  if (!child.IsDefined()) return std::nullopt;
  return lookup(child, segs, i + 1);
}

void set_path(YAML::Node node, const std::vector<std::string>& segs, std::size_t i,
              const YAML::Node& value) {
  if (i + 1 == segs.size()) {
    node[segs[i]] = value;
    return;
  }
  YAML::Node child = node[segs[i]];
  if (!child.IsMap()) child = YAML::Node(YAML::NodeType::Map);
  set_path(child, segs, i + 1, value);
}

bool is_plugin_section(const DocumentRules& rules, const std::string& section) {
  const auto& sections = rules.plugin_sections;
  return std::find(sections.begin(), sections.end(), section) != sections.end();
}

}  // namespace detail

namespace {

bool starts_with_key(const std::string& key, const std::string& prefix) {
  return key == prefix || (key.size() > prefix.size() &&
                           key.compare(0, prefix.size(), prefix) == 0 && key[prefix.size()] == '.');
}

// Every key path of `node`'s maps ("a", "a.b", ...), to test many keys for presence at once.
void collect_paths(const YAML::Node& node, const std::string& prefix,
                   std::unordered_set<std::string>& out) {
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    std::string key = prefix.empty() ? kv.first.Scalar() : prefix + "." + kv.first.Scalar();
    collect_paths(kv.second, key, out);
    out.insert(std::move(key));
  }
}

}  // namespace

ConfigDocument::ConfigDocument(YAML::Node tree, std::string source, std::string base_dir,
                               std::set<std::string> cli_keys,
                               std::map<std::string, Origin> origins,
                               const std::vector<std::string>& overrides, DocumentRules rules)
    : source_(std::move(source)),
      base_dir_(std::move(base_dir)),
      cli_keys_(std::move(cli_keys)),
      origins_(std::move(origins)),
      rules_(std::move(rules)) {
  for (const auto& a : overrides) detail::apply_assignment(tree, a, cli_keys_, rules_);
  if (!tree.IsDefined() || tree.IsNull()) tree = YAML::Node(YAML::NodeType::Map);
  yaml_bounds::check_expanded_size(tree, source_);  // --set values may hold aliases too
  if (!origins_.empty()) {  // forget the keys an override removed (one walk, not a lookup each)
    std::unordered_set<std::string> present;
    collect_paths(tree, "", present);
    std::erase_if(origins_, [&](const auto& kv) { return present.count(kv.first) == 0; });
  }
  // A null value means "not set": `rewriter: ~` removes the optional section, `--set x=null`
  // restores a default.
  tree_ = yaml_bounds::without_nulls(tree);
  std::error_code ec;
  cwd_ = fs::current_path(ec).string();
}

ConfigDocument ConfigDocument::read(const std::string& file,
                                    const std::vector<std::string>& overrides,
                                    DocumentRules rules) {
  const fs::path abs = fs::absolute(file).lexically_normal();
  std::error_code ec;
  std::vector<std::string> chain{fs::weakly_canonical(abs, ec).string()};
  detail::Layered layers = detail::load_layers(file, file, chain, rules);
  return ConfigDocument(layers.root, file, abs.parent_path().string(), {},
                        std::move(layers.origins), overrides, std::move(rules));
}

ConfigDocument ConfigDocument::parse(const std::string& text, const std::string& source,
                                     const std::string& base_dir,
                                     const std::vector<std::string>& overrides,
                                     DocumentRules rules) {
  return ConfigDocument(detail::parse_yaml(text, source), source, base_dir, {}, {}, overrides,
                        std::move(rules));
}

ConfigDocument ConfigDocument::with(const std::string& assignment) const {
  return ConfigDocument(YAML::Clone(tree_), source_, base_dir_, cli_keys_, origins_, {assignment},
                        rules_);
}

std::optional<YAML::Node> ConfigDocument::find(const std::string& key) const {
  return detail::lookup(tree_, detail::split_key(key));
}

bool ConfigDocument::written(const std::string& key) const {
  return cli_keys_.count(key) || find(key).has_value();
}

// A path nobody wrote (the schema's default) resolves against the defaults' directory, wherever
// the config that left it out lives (docs/configuration.md).
std::string ConfigDocument::resolve_path_of(const std::string& key, const std::string& path) const {
  if (cli_keys_.count(key)) return resolve_against(cwd_, path);
  if (auto it = origins_.find(key); it != origins_.end())
    return resolve_against(it->second.dir, path);
  if (!written(key)) return resolve_against(rules_.defaults_dir, path);
  return resolve_against(base_dir_, path);
}

std::string ConfigDocument::path_origin(const std::string& key, const std::string& value) const {
  if (cli_keys_.count(key))
    return key + value + " from --set: relative to the current directory " + cwd_;
  if (auto it = origins_.find(key); it != origins_.end())
    return key + value + " from " + it->second.file + " (extended by " + source_ +
           "): relative to its directory " + it->second.dir;
  if (!written(key))
    return key + value + " (the default, written in no config): relative to the default " +
           "configs directory " + rules_.defaults_dir;
  return key + value + " from " + source_ + ": relative to its directory " + base_dir_;
}

std::string ConfigDocument::where_written(const std::string& message) const {
  const std::size_t open = message.find('\'');
  const std::size_t close = open == std::string::npos ? open : message.find('\'', open + 1);
  if (close == std::string::npos) return source_;
  const std::string subject = message.substr(open + 1, close - open - 1);
  if (cli_keys_.count(subject)) return source_;
  for (const auto& [key, origin] : origins_)
    if (starts_with_key(key, subject)) return origin.file + " (extended by " + source_ + ")";
  return source_;
}

std::string resolve_against(const std::string& base, const std::string& path) {
  if (path.empty()) return path;
  if (path == "~" || path.rfind("~/", 0) == 0) {
    const char* home = std::getenv("HOME");
    return (fs::path(home ? home : "") / path.substr(path.size() > 1 ? 2 : 1)).string();
  }
  const fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(base) / p).lexically_normal().string();
}

}  // namespace flipper::toolkit::config
