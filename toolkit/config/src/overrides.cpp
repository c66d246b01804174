// --set key.path=value: one overlay of a config document (docs/configuration.md).
#include <yaml-cpp/yaml.h>

#include <cctype>
#include <set>
#include <string>
#include <vector>

#include "yaml_tree.hpp"

namespace flipper::toolkit::config::detail {
namespace {

bool is_valid_key(const std::string& key) {
  if (key.empty() || key.front() == '.' || key.back() == '.' || key.find("..") != std::string::npos)
    return false;
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      return false;
  return true;
}

bool is_null_word(const std::string& text) {
  return text == "~" || text == "null" || text == "Null" || text == "NULL";
}

bool is_quoted(const std::string& text) {
  return text.size() >= 2 && (text.front() == '"' || text.front() == '\'') &&
         text.back() == text.front();
}

// `<plugin section>.params.<name>`: a plugin parameter, whose type only the plugin's schema knows.
bool is_plugin_param(const std::vector<std::string>& segs, const DocumentRules& rules) {
  return segs.size() == 3 && segs[1] == "params" && is_plugin_section(rules, segs[0]);
}

YAML::Node parse_value(const std::string& text, const std::string& malformed) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(malformed + ": the value is not a YAML scalar or flow value (" + e.msg + ")");
  }
}

// The value of one --set. Text keys (String/Path keys, plugin params) take the text verbatim —
// YAML would read `:memory:` as a map and `a #b` as `a` — unless it is quoted (then unquoted as
// YAML does), a null word (unsets), or, for a plugin param, a flow list or map (its type is
// unknown here; a StringList param needs `[a, b]`). Other keys are parsed as YAML.
YAML::Node assignment_value(const std::string& key, const std::vector<std::string>& segs,
                            const std::string& text, const std::string& malformed,
                            const DocumentRules& rules) {
  const bool text_key = rules.is_text_key && rules.is_text_key(key);
  const bool param = is_plugin_param(segs, rules);
  if (!text_key && !param) {
    if (text.empty()) fail(malformed + ": the value is empty (use null to unset a key)");
    return parse_value(text, malformed);
  }
  if (is_null_word(text)) return YAML::Node(YAML::NodeType::Null);
  if (is_quoted(text)) {
    const YAML::Node v = parse_value(text, malformed);
    if (!v.IsScalar()) fail(malformed + ": the quoted value is not one string");
    return YAML::Node(v.Scalar());
  }
  if (param && !text.empty() && (text.front() == '[' || text.front() == '{'))
    return parse_value(text, malformed);
  return YAML::Node(text);
}

// `--set SECTION.plugin=NAME` that selects another plugin than the files did: the files' params
// belong to the other plugin, so they go, as they do when an `extends` overlay switches the
// plugin (docs/configuration.md). Params given by an earlier --set stay: the user asked for them.
void drop_other_plugin_params(YAML::Node& root, const std::string& section,
                              const YAML::Node& plugin, const std::set<std::string>& cli_keys,
                              const DocumentRules& rules) {
  if (!is_plugin_section(rules, section)) return;
  YAML::Node sec = root[section];
  if (!sec.IsMap() || !sec["plugin"].IsScalar() || !plugin.IsScalar() ||
      sec["plugin"].Scalar() == plugin.Scalar() || !sec["params"].IsDefined())
    return;
  const YAML::Node old_params = sec["params"];
  YAML::Node kept(YAML::NodeType::Map);
  if (old_params.IsMap())
    for (const auto& kv : old_params)
      if (cli_keys.count(section + ".params." + kv.first.Scalar()))
        kept[kv.first.Scalar()] = YAML::Clone(kv.second);
  sec.remove("params");
  if (kept.size() > 0) sec["params"] = kept;
}

}  // namespace

void apply_assignment(YAML::Node& root, const std::string& assignment,
                      std::set<std::string>& cli_keys, const DocumentRules& rules) {
  const std::size_t eq = assignment.find('=');
  const std::string malformed = "malformed --set '" + assignment + "'";
  if (eq == std::string::npos)
    fail(malformed + ": expected key.path=value (e.g. --set planner.plugin=astar)");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  if (!is_valid_key(key)) fail(malformed + ": '" + key + "' is not a dotted key path");
  const auto segs = split_key(key);
  const YAML::Node value = assignment_value(key, segs, text, malformed, rules);
  if (!root.IsMap()) root = YAML::Node(YAML::NodeType::Map);
  if (segs.size() == 2 && segs[1] == "plugin")
    drop_other_plugin_params(root, segs[0], value, cli_keys, rules);
  cli_keys.insert(key);
  set_path(root, segs, 0, value);
}

}  // namespace flipper::toolkit::config::detail
