#include "schema.hpp"

#include <algorithm>

namespace flipper::kernel::detail {
namespace {
using T = KeyType;
constexpr bool kRequired = true;
constexpr bool kOptional = true;

// Adding a kernel key is one line here. Defaults are YAML text; keep configs/default.yaml listing
// the same values so the file documents them.
const std::vector<KeySpec> kSchema = {
    {"world.plugin", T::String, "grid2d", "", kRequired},
    {"world.file", T::Path, "worlds/study2018.json", ""},
    {"world.params", T::Map, "{}", ""},
    {"planner.plugin", T::String, "astar", "", kRequired},
    {"planner.params", T::Map, "{}", ""},
    {"parser.plugin", T::String, "chart", "", kRequired},
    {"parser.params", T::Map, "{}", ""},
    {"scorer.plugin", T::String, "loglinear", "", kRequired},
    {"scorer.params", T::Map, "{}", ""},
    {"rewriter.plugin", T::String, "", "", kRequired, kOptional},
    {"rewriter.params", T::Map, "{}", "", false, kOptional},
    {"similarity.plugin", T::String, "", "", kRequired, kOptional},
    {"similarity.params", T::Map, "{}", "", false, kOptional},
    {"grammar.file", T::Path, "grammars/core.grammar", ""},
    {"grammar.colors", T::StringList,
     "[black, blue, gray, green, orange, pink, purple, red, yellow]", ""},
    {"grammar.shapes", T::StringList, "[triangle, circle, square]", ""},
    {"grammar.directions", T::StringList, "[up, down, left, right]", ""},
    {"lexicon.path", T::Path, "~/.local/share/flipper/lexicon.sqlite", ""},
    {"lexicon.sharing", T::String, "shared", "shared|private|core"},
    {"lexicon.preload", T::Path, "''", ""},
    {"lexicon.weights", T::String, "global", "global|per_user"},
    {"lexicon.busy_timeout_ms", T::Int, "10000", "1..600000"},
    {"induction.alignment", T::Bool, "true", ""},
    {"induction.generalize", T::Bool, "true", ""},
    {"induction.perturbed_checks", T::Int, "0", "0..1000"},
    {"execution.action_budget", T::Int, "100000", "1..1000000000000"},
    {"execution.time_budget_ms", T::Int, "2000", "1..86400000"},
    {"execution.while_limit", T::Int, "20", "0..1000000"},
    {"input.max_chars", T::Int, "2000", "1..100000000"},
    {"input.max_semicolons", T::Int, "30", "1..1000000"},
    {"session.k", T::Int, "3", "1..1000"},
    {"plugin_paths", T::PathList, "[]", ""},
    {"serve.host", T::String, "127.0.0.1", ""},
    {"serve.port", T::Int, "8410", "0..65535"},
    {"serve.threads", T::Int, "128", "1..4096"},
    {"serve.max_request_bytes", T::Int, "65536", "256..67108864"},
    {"serve.rate_per_second", T::Int, "100", "1..1000000"},
    {"serve.rate_burst", T::Int, "200", "1..1000000"},
    {"serve.max_sessions", T::Int, "1000", "1..1000000"},
    {"serve.session_idle_s", T::Int, "3600", "1..31536000"},
    {"serve.web_dir", T::Path, "''", ""},
    {"serve.study", T::Path, "''", ""},
};
}  // namespace

const std::vector<KeySpec>& kernel_schema() {
  return kSchema;
}

const KeySpec* find_key(std::string_view path) {
  for (const auto& k : kSchema)
    if (k.path == path) return &k;
  return nullptr;
}

bool is_section(std::string_view prefix) {
  for (const auto& k : kSchema)
    if (k.path.size() > prefix.size() && k.path.substr(0, prefix.size()) == prefix &&
        k.path[prefix.size()] == '.')
      return true;
  return false;
}

std::vector<std::string> child_names(std::string_view prefix) {
  std::vector<std::string> out;
  const std::size_t skip = prefix.empty() ? 0 : prefix.size() + 1;
  for (const auto& k : kSchema) {
    if (!prefix.empty() && !(k.path.size() > skip && k.path.substr(0, prefix.size()) == prefix &&
                             k.path[prefix.size()] == '.'))
      continue;
    std::string_view rest = k.path.substr(skip);
    std::string name(rest.substr(0, rest.find('.')));
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  return out;
}

const char* describe(KeyType type) {
  switch (type) {
    case T::Bool:
      return "a boolean (true/false)";
    case T::Int:
      return "an integer";
    case T::String:
      return "a string";
    case T::Path:
      return "a path";
    case T::StringList:
      return "a list of strings";
    case T::PathList:
      return "a list of paths";
    case T::Map:
      return "a map";
  }
  return "?";
}

}  // namespace flipper::kernel::detail
