#include "schema.hpp"

#include <algorithm>
#include <string>

#include "flipper/kernel/keys.hpp"

namespace flipper::kernel::detail {
namespace {
using T = KeyType;
constexpr bool kRequired = true;
constexpr bool kOptional = true;

// A row from a typed declaration of keys.hpp: its default and range are not restated here.
KeySpec row(const keys::Int& k) {
  return {std::string(k.path), T::Int, std::to_string(k.def),
          std::to_string(k.min) + ".." + std::to_string(k.max)};
}

// Adding a kernel key is one line here (plus one in keys.hpp when code needs its default).
// Defaults are YAML text; configs/default.yaml does not restate them.
const std::vector<KeySpec> kSchema = {
    {"world.plugin", T::String, "grid2d", "", kRequired},
    {"world.file", T::Path, "worlds/study2018.json", ""},
    {"world.params", T::Map, "{}", ""},
    {"world.resolution", T::Number, "1.0", ">0"},      // metres per cell (plans over DDS)
    {"world.origin", T::NumberList, "[0, 0, 0]", ""},  // metres of cell (0,0,0)
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
    {"grammar.directions", T::StringList, "[]", ""},  // empty: the world plugin's words
    {"lexicon.path", T::Path, "~/.local/share/flipper/lexicon.sqlite", ""},
    {"lexicon.sharing", T::String, "shared", "shared|private|core"},
    {"lexicon.preload", T::Path, "''", ""},
    {"lexicon.weights", T::String, "global", "global|per_user"},
    row(keys::kBusyTimeoutMs),
    row(keys::kSnapshotMinRules),
    {"lexicon.replication", T::String, "none", "none|dds"},
    {"lexicon.site", T::String, "''", ""},
    {"publish.plans", T::String, "none", "none|dds"},
    {"dds.domain", T::Int, "0", "0..232"},
    {"dds.interfaces", T::StringList, "[]", ""},
    {"dds.config", T::String, "''", ""},
    {"induction.alignment", T::Bool, "true", ""},
    {"induction.generalize", T::Bool, "true", ""},
    row(keys::kPerturbedChecks),
    row(keys::kActionBudget),
    row(keys::kTimeBudgetMs),
    row(keys::kWhileLimit),
    row(keys::kMaxChars),
    row(keys::kMaxSemicolons),
    row(keys::kMaxLineBytes),
    row(keys::kMaxJsonDepth),
    row(keys::kMaxTokens),
    row(keys::kMaxBodyLines),
    row(keys::kMaxFileBytes),
    row(keys::kMaxWorldCells),
    row(keys::kSessionK),
    row(keys::kDeadlineMs),
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
    std::string_view rest = std::string_view(k.path).substr(skip);
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
    case T::Number:
      return "a number";
    case T::NumberList:
      return "a list of numbers";
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
