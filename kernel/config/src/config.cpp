// Config loading: file (or the embedded default), over the files it `extends` -> --set overrides
// -> drop nulls -> read the YAML tree into typed values (to_given) -> validate them against the
// kernel schema (keys.cpp) with the SDK's engine, which fills defaults. Plugin params go through
// the same two steps against the plugin's schema.
#include "flipper/kernel/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/yaml_bounds.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"

namespace flipper::kernel {
namespace detail {
extern const char* const kEmbeddedDefaultConfig;  // generated from configs/default.yaml
}

namespace fs = std::filesystem;

struct ConfigOrigin {
  std::string file;
  std::string dir;
};
using sdk::Error;
using sdk::ParamType;
namespace codes = sdk::codes;

struct Config::Impl {
  YAML::Node given;    // the merged tree as written (no nulls); plugin params are read from it
  sdk::Params values;  // the kernel keys, validated, defaults filled; never mutated once shared
  std::string source;
  std::string base_dir;
  std::set<std::string> cli_keys;  // keys given by --set: their paths resolve against `cwd`
  std::string cwd;                 // the current directory when the config was loaded
  // Keys whose value came from a file this one extends: file and directory they resolve against.
  std::map<std::string, ConfigOrigin> origins;
};

namespace {

constexpr const char* kEmbeddedSource = "<embedded default>";

[[noreturn]] void fail(const std::string& message) {
  throw Error(codes::kBadConfig, message);
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

// Looks a dotted key up without creating anything (yaml-cpp's Node assignment aliases, so
// navigation is by recursion over fresh handles).
std::optional<YAML::Node> lookup(const YAML::Node& node, const std::vector<std::string>& segs,
                                 std::size_t i = 0) {
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
bool is_plugin_param(const std::vector<std::string>& segs) {
  if (segs.size() != 3 || segs[1] != "params") return false;
  const auto& sections = Config::plugin_sections();
  return std::find(sections.begin(), sections.end(), segs[0]) != sections.end();
}

YAML::Node parse_value(const std::string& text, const std::string& malformed) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(malformed + ": the value is not a YAML scalar or flow value (" + e.msg + ")");
  }
}

// The value of one --set. Text keys (kernel String/Path keys, plugin params) take the text
// verbatim — YAML would read `:memory:` as a map and `a #b` as `a` — unless it is quoted (then
// unquoted as YAML does), a null word (unsets), or, for a plugin param, a flow list or map (its
// type is unknown here; a StringList param needs `[a, b]`). Other keys are parsed as YAML.
YAML::Node assignment_value(const std::vector<std::string>& segs, const std::string& text,
                            const std::string& malformed) {
  std::string key;
  for (const auto& s : segs) key += (key.empty() ? "" : ".") + s;
  const sdk::ParamSpec* spec = Config::schema().find(key);
  const bool text_key =
      spec != nullptr && (spec->type == ParamType::String || spec->type == ParamType::Path);
  const bool param = is_plugin_param(segs);
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
                              const YAML::Node& plugin, const std::set<std::string>& cli_keys) {
  const auto& sections = Config::plugin_sections();
  if (std::find(sections.begin(), sections.end(), section) == sections.end()) return;
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

void apply_assignment(YAML::Node& root, const std::string& assignment,
                      std::set<std::string>& cli_keys) {
  const std::size_t eq = assignment.find('=');
  const std::string malformed = "malformed --set '" + assignment + "'";
  if (eq == std::string::npos)
    fail(malformed + ": expected key.path=value (e.g. --set planner.plugin=astar)");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  if (!is_valid_key(key)) fail(malformed + ": '" + key + "' is not a dotted key path");
  const auto segs = split_key(key);
  const YAML::Node value = assignment_value(segs, text, malformed);
  if (!root.IsMap()) root = YAML::Node(YAML::NodeType::Map);
  if (segs.size() == 2 && segs[1] == "plugin")
    drop_other_plugin_params(root, segs[0], value, cli_keys);
  cli_keys.insert(key);
  set_path(root, segs, 0, value);
}

std::string scalar_text(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  return "null";
}

std::optional<std::int64_t> parse_int(const std::string& s) {
  std::int64_t v = 0;
  const char* end = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), end, v);
  if (ec != std::errc() || p != end) return std::nullopt;
  return v;
}

// Resolves a Path value of a key (plugin params resolve at load; kernel keys on access).
using PathFn = std::function<std::string(const std::string& key, const std::string& text)>;

[[noreturn]] void wrong_type(const std::string& key, ParamType type, const YAML::Node& v) {
  fail("config key '" + key + "' must be " + sdk::type_phrase(type) + ", got " + scalar_text(v));
}

std::vector<std::string> scalar_list(const std::string& key, ParamType type, const YAML::Node& v) {
  if (!v.IsSequence()) wrong_type(key, type, v);
  std::vector<std::string> out;
  for (const auto& e : v) {
    double d = 0;
    const bool ok = e.IsScalar() && (type != ParamType::DoubleList ||
                                     (YAML::convert<double>::decode(e, d) && std::isfinite(d)));
    if (!ok)
      fail("config key '" + key + "' must be " + sdk::type_phrase(type) + ", but an element is " +
           scalar_text(e));
    out.push_back(e.Scalar());
  }
  return out;
}

// One YAML value as the typed value `spec` declares; a value of the wrong shape is an error
// worded as the engine words its own type errors.
sdk::ParamValue typed_value(const sdk::ParamSpec& spec, const std::string& key, const YAML::Node& v,
                            const PathFn& path) {
  switch (spec.type) {
    case ParamType::Bool: {
      bool b = false;
      if (!v.IsScalar() || !YAML::convert<bool>::decode(v, b)) wrong_type(key, spec.type, v);
      return b;
    }
    case ParamType::Int: {
      const auto x = v.IsScalar() ? parse_int(v.Scalar()) : std::nullopt;
      if (!x) wrong_type(key, spec.type, v);
      return *x;
    }
    case ParamType::Double: {
      double d = 0;
      if (!v.IsScalar() || !YAML::convert<double>::decode(v, d) || !std::isfinite(d))
        wrong_type(key, spec.type, v);
      return d;
    }
    case ParamType::String:
      if (!v.IsScalar()) wrong_type(key, spec.type, v);
      return v.Scalar();
    case ParamType::Path:
      if (!v.IsScalar()) wrong_type(key, spec.type, v);
      return path(key, v.Scalar());
    case ParamType::StringList:
      return scalar_list(key, spec.type, v);
    case ParamType::DoubleList: {
      (void)scalar_list(key, spec.type, v);  // each element a finite number, else the error
      std::vector<double> numbers;
      for (const auto& e : v) numbers.push_back(e.as<double>());
      return numbers;
    }
    case ParamType::PathList: {
      std::vector<std::string> list = scalar_list(key, spec.type, v);
      for (auto& p : list) p = path(key, p);
      return list;
    }
    case ParamType::Map: {
      if (!v.IsMap()) wrong_type(key, spec.type, v);
      std::vector<std::string> names;
      for (const auto& kv : v) names.push_back(kv.first.Scalar());
      return names;
    }
  }
  wrong_type(key, spec.type, v);
}

// Reads the YAML map `node` (at schema name `inner`, full key `where` + `inner`) into dotted
// names for sdk::validate_params: declared keys typed, sections descended, an unknown key passed
// on as is (the engine names it, with a hint among its siblings).
void to_given(const YAML::Node& node, const sdk::ParamSchema& schema, const std::string& where,
              const std::string& inner, const PathFn& path,
              std::map<std::string, sdk::ParamValue>& given) {
  for (const auto& kv : node) {
    const std::string name = inner.empty() ? kv.first.Scalar() : inner + "." + kv.first.Scalar();
    const std::string key = where.empty() ? name : where + "." + name;
    if (const sdk::ParamSpec* spec = schema.find(name)) {
      given[name] = typed_value(*spec, key, kv.second, path);
    } else if (schema.is_section(name)) {
      if (!kv.second.IsMap())
        fail("config key '" + key + "' must be a map (a section of keys), got " +
             scalar_text(kv.second));
      to_given(kv.second, schema, where, name, path, given);
    } else {
      given[name] = std::string();
    }
  }
}

// The kernel keys of a merged tree, validated with defaults filled.
sdk::Params kernel_values(const YAML::Node& root) {
  if (!root.IsMap()) fail("a config must be a YAML map of sections, got " + scalar_text(root));
  std::map<std::string, sdk::ParamValue> given;
  const PathFn as_written = [](const std::string&, const std::string& text) { return text; };
  to_given(root, Config::schema(), "", "", as_written, given);
  return sdk::validate_params(Config::schema(), given, "");
}

YAML::Node yaml_of(const sdk::ParamValue& v) {
  if (const auto* b = std::get_if<bool>(&v)) return YAML::Node(*b);
  if (const auto* i = std::get_if<std::int64_t>(&v)) return YAML::Node(*i);
  if (const auto* d = std::get_if<double>(&v)) {
    // The shortest text that reads back as the same double (yaml-cpp 0.7 writes 17 digits).
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, *d).ptr;
    return YAML::Node(std::string(text, end));
  }
  if (const auto* s = std::get_if<std::string>(&v)) return YAML::Node(*s);
  YAML::Node list(YAML::NodeType::Sequence);
  if (const auto* numbers = std::get_if<std::vector<double>>(&v)) {
    for (double d : *numbers) list.push_back(yaml_of(d));
    return list;
  }
  for (const auto& e : std::get<std::vector<std::string>>(v)) list.push_back(e);
  return list;
}

std::string default_config_dir() {
  // Relative to the executable only (no source path compiled in): the install layout
  // <exe>/../share/flipper/configs, which the build tree mirrors with a link to the source
  // configs/. Resolved through the link, so paths read as the files' own.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "configs";
  const fs::path dir = exe.parent_path().parent_path() / "share/flipper/configs";
  const fs::path real = fs::canonical(dir, ec);
  return ec ? dir.string() : real.string();
}

bool starts_with_key(const std::string& key, const std::string& prefix) {
  return key == prefix || (key.size() > prefix.size() &&
                           key.compare(0, prefix.size(), prefix) == 0 && key[prefix.size()] == '.');
}

// The file a bad key was written in, for its message: the key a message is about is the first
// one it quotes; when that key (or a key below it) came from a file `source` extends, the
// message names that file.
std::string where_written(const std::string& message, const std::string& source,
                          const std::set<std::string>& cli_keys,
                          const std::map<std::string, ConfigOrigin>& origins) {
  const std::size_t open = message.find('\'');
  const std::size_t close = open == std::string::npos ? open : message.find('\'', open + 1);
  if (close == std::string::npos) return source;
  const std::string subject = message.substr(open + 1, close - open - 1);
  if (cli_keys.count(subject)) return source;
  for (const auto& [key, origin] : origins)
    if (starts_with_key(key, subject)) return origin.file + " (extended by " + source + ")";
  return source;
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

Config build(YAML::Node root, std::string source, std::string base_dir,
             const std::vector<std::string>& overrides, std::set<std::string> cli_keys = {},
             std::map<std::string, ConfigOrigin> origins = {}) {
  for (const auto& a : overrides) apply_assignment(root, a, cli_keys);
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  yaml_bounds::check_expanded_size(root, source);  // --set values may hold aliases too
  if (!origins.empty()) {  // forget the keys an override removed (one walk, not a lookup each)
    std::unordered_set<std::string> present;
    collect_paths(root, "", present);
    std::erase_if(origins, [&](const auto& kv) { return present.count(kv.first) == 0; });
  }
  auto impl = std::make_shared<Config::Impl>();
  // A null value means "not set": `rewriter: ~` removes the optional section, `--set x=null`
  // restores a default.
  impl->given = yaml_bounds::without_nulls(root);
  try {
    impl->values = kernel_values(impl->given);
  } catch (const Error& e) {
    throw Error(e.code(),
                "config " + where_written(e.what(), source, cli_keys, origins) + ": " + e.what());
  }
  impl->source = std::move(source);
  impl->base_dir = std::move(base_dir);
  impl->cli_keys = std::move(cli_keys);
  impl->origins = std::move(origins);
  std::error_code ec;
  impl->cwd = fs::current_path(ec).string();
  return Config(std::move(impl));
}

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

// --- extends: a config overlays another (docs/configuration.md) ----------------------------

constexpr std::size_t kMaxExtendsDepth = 16;

// A config file is small: a regular file of at most yaml_bounds::kMaxConfigBytes (a fixed limit,
// since the config cannot set its own), so /dev/zero or a FIFO is an error, not a hang, and a
// huge document is refused before yaml-cpp reads it (about 75 MB of nodes per MiB of YAML).
std::string read_config_file(const std::string& path) {
  try {
    return read_regular_file(path, yaml_bounds::kMaxConfigBytes, "config file", codes::kBadConfig);
  } catch (const Error& e) {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (std::string(e.code()) == codes::kFileTooLarge && !ec)
      fail("config file '" + path + "' has " + std::to_string(bytes) +
           " bytes; the limit for a config is " + std::to_string(yaml_bounds::kMaxConfigBytes) +
           " bytes (1 MiB)");
    fail(e.what());  // every config problem is bad_config (exit status 2)
  }
}

// Forgets the origins of `prefix` and every key below it (`prefix.*`, a contiguous range).
void erase_below(std::map<std::string, ConfigOrigin>& origins, const std::string& prefix) {
  origins.erase(prefix);
  origins.erase(origins.lower_bound(prefix + "."), origins.lower_bound(prefix + "/"));
}

// Records `origin` for every leaf under `node` that has none yet (deeper bases recorded theirs).
void record_leaves(const YAML::Node& node, const std::string& prefix, const ConfigOrigin& origin,
                   std::map<std::string, ConfigOrigin>& origins) {
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
                 std::map<std::string, ConfigOrigin>& origins) {
  if (!base.IsMap() || !overlay.IsMap()) {
    erase_below(origins, prefix);
    return overlay;
  }
  const auto& sections = Config::plugin_sections();
  const bool plugin_section = std::find(sections.begin(), sections.end(), prefix) != sections.end();
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
      YAML::Node merged = merge(it->second, kv.second, key, origins);
      if (!merged.is(it->second)) it->second = merged;
    } else {
      erase_below(origins, key);
      base.force_insert(kv.first, kv.second);
      at.emplace(name, kv.second);
    }
  }
  return base;
}

struct Layered {
  YAML::Node root;
  std::map<std::string, ConfigOrigin> origins;  // keys that came from extended files
};

// Reads `file` (named `shown` in messages) and, when it says `extends: BASE`, the chain of files
// below it. `chain` holds the canonical paths being read, to refuse cycles.
Layered load_layers(const std::string& file, const std::string& shown,
                    std::vector<std::string>& chain) {
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
  Layered below = load_layers(base, base, chain);
  chain.pop_back();
  record_leaves(below.root, "", {base, fs::path(base).parent_path().string()}, below.origins);
  root.remove("extends");
  below.root = merge(below.root, root, "", below.origins);
  return below;
}

// A key below a plugin section's params (not a kernel key): read from the tree as written.
YAML::Node node_at(const Config::Impl& impl, const std::string& key) {
  auto v = lookup(impl.given, split_key(key));
  if (!v) fail("config key '" + key + "' is not set");
  return *v;
}

// A kernel key: its validated value, or null for a key below a plugin's params.
const sdk::Params* kernel_key(const Config::Impl& impl, const std::string& key) {
  if (Config::schema().find(key) == nullptr) return nullptr;
  if (!impl.values.has(key)) fail("config key '" + key + "' is not set");
  return &impl.values;
}

}  // namespace

Config::Config(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

Config Config::load(const std::optional<std::string>& file,
                    const std::vector<std::string>& overrides) {
  if (!file) {
    return build(parse_yaml(detail::kEmbeddedDefaultConfig, kEmbeddedSource), kEmbeddedSource,
                 default_config_dir(), overrides);
  }
  const fs::path abs = fs::absolute(*file).lexically_normal();
  std::error_code ec;
  std::vector<std::string> chain{fs::weakly_canonical(abs, ec).string()};
  Layered layers = load_layers(*file, *file, chain);
  return build(layers.root, *file, abs.parent_path().string(), overrides, {},
               std::move(layers.origins));
}

Config Config::embedded_default() {
  return load(std::nullopt, {});
}

const std::string& Config::source() const {
  return impl_->source;
}
const std::string& Config::base_dir() const {
  return impl_->base_dir;
}

std::string Config::resolve_path(const std::string& path) const {
  return resolve_against(impl_->base_dir, path);
}

// A path nobody wrote (the schema's default) resolves against the directory of the embedded
// default config, wherever the config that left it out lives (docs/configuration.md).
bool Config::written(const std::string& key) const {
  return impl_->cli_keys.count(key) || lookup(impl_->given, split_key(key)).has_value();
}

std::string Config::resolve_path_of(const std::string& key, const std::string& path) const {
  if (impl_->cli_keys.count(key)) return resolve_against(impl_->cwd, path);
  if (auto it = impl_->origins.find(key); it != impl_->origins.end())
    return resolve_against(it->second.dir, path);
  if (!written(key)) return resolve_against(default_config_dir(), path);
  return resolve_against(impl_->base_dir, path);
}

std::string Config::path_origin(const std::string& key) const {
  const sdk::ParamSpec* spec = schema().find(key);
  const auto node = lookup(impl_->given, split_key(key));
  const std::string value =
      spec != nullptr && spec->type == ParamType::Path && impl_->values.has(key)
          ? " '" + impl_->values.get_string(key) + "'"
      : node && node->IsScalar() ? " '" + node->Scalar() + "'"
                                 : "";
  if (impl_->cli_keys.count(key))
    return key + value + " from --set: relative to the current directory " + impl_->cwd;
  if (auto it = impl_->origins.find(key); it != impl_->origins.end())
    return key + value + " from " + it->second.file + " (extended by " + impl_->source +
           "): relative to its directory " + it->second.dir;
  if (!written(key))
    return key + value + " (the default, written in no config): relative to the default " +
           "configs directory " + default_config_dir();
  return key + value + " from " + impl_->source + ": relative to its directory " + impl_->base_dir;
}

const sdk::Params& Config::declared(std::string_view key) const {
  if (schema().find(std::string(key)) == nullptr)
    throw std::logic_error("config key '" + std::string(key) +
                           "' is not in the installed schema (docs/config.md \"Who declares a "
                           "key\")");
  return impl_->values;
}

bool Config::has(const std::string& key) const {
  if (schema().find(key) != nullptr) return impl_->values.has(key);
  return lookup(impl_->given, split_key(key)).has_value();
}

std::string Config::get_string(const std::string& key) const {
  if (const auto* v = kernel_key(*impl_, key)) return v->get_string(key);
  const YAML::Node n = node_at(*impl_, key);
  if (!n.IsScalar()) fail("config key '" + key + "' is not a string");
  return n.Scalar();
}

std::int64_t Config::get_int(const std::string& key) const {
  if (const auto* v = kernel_key(*impl_, key)) return v->get_int(key);
  const YAML::Node n = node_at(*impl_, key);
  const auto v = n.IsScalar() ? parse_int(n.Scalar()) : std::nullopt;
  if (!v) fail("config key '" + key + "' is not an integer");
  return *v;
}

double Config::get_double(const std::string& key) const {
  if (const auto* v = kernel_key(*impl_, key)) return v->get_double(key);
  const YAML::Node n = node_at(*impl_, key);
  double d = 0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, d))
    fail("config key '" + key + "' is not a number");
  return d;
}

bool Config::get_bool(const std::string& key) const {
  if (const auto* v = kernel_key(*impl_, key)) return v->get_bool(key);
  const YAML::Node n = node_at(*impl_, key);
  bool b = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, b))
    fail("config key '" + key + "' is not a boolean");
  return b;
}

std::vector<std::string> Config::get_string_list(const std::string& key) const {
  if (const auto* v = kernel_key(*impl_, key)) return v->get_string_list(key);
  const YAML::Node n = node_at(*impl_, key);
  if (!n.IsSequence()) fail("config key '" + key + "' is not a list");
  std::vector<std::string> out;
  for (const auto& e : n) out.push_back(e.Scalar());
  return out;
}

std::string Config::get_path(const std::string& key) const {
  return resolve_path_of(key, get_string(key));
}

std::vector<std::string> Config::get_path_list(const std::string& key) const {
  std::vector<std::string> out = get_string_list(key);
  for (auto& p : out) p = resolve_path_of(key, p);
  return out;
}

void Config::set(const std::string& assignment) {
  *this = build(YAML::Clone(impl_->given), impl_->source, impl_->base_dir, {assignment},
                impl_->cli_keys, impl_->origins);
}

namespace {
// Empty maps print as `params: {}` on one line (block style would put `{}` on its own line).
void flow_empty_maps(YAML::Node node) {
  if (!node.IsMap()) return;
  if (node.size() == 0) node.SetStyle(YAML::EmitterStyle::Flow);
  for (auto kv : node) flow_empty_maps(kv.second);
}
}  // namespace

std::string Config::dump() const {
  // Schema order, each value in its type's one spelling (`off` -> false, `1.0` -> 1), a plugin's
  // params as written (its own schema is the loader's business).
  YAML::Node copy(YAML::NodeType::Map);
  for (const auto& spec : schema().params) {
    if (!impl_->values.has(spec.name)) continue;
    const auto segs = split_key(spec.name);
    const auto written = lookup(impl_->given, segs);
    YAML::Node value = spec.type != ParamType::Map ? yaml_of(impl_->values.values().at(spec.name))
                       : written                   ? YAML::Clone(*written)
                                                   : YAML::Node(YAML::NodeType::Map);
    set_path(copy, segs, 0, value);
  }
  flow_empty_maps(copy);
  YAML::Emitter out;
  out.SetSeqFormat(YAML::Flow);
  out << copy;
  return std::string(out.c_str()) + "\n";
}

const std::vector<std::string>& Config::plugin_sections() {
  static const std::vector<std::string> kSections = {"world",  "planner",  "parser",
                                                     "scorer", "rewriter", "similarity"};
  return kSections;
}

sdk::Params Config::plugin_params(const std::string& section,
                                  const sdk::ParamSchema& schema) const {
  const std::string where = section + ".params";
  const PathFn resolve = [this](const std::string& key, const std::string& text) {
    return resolve_path_of(key, text);
  };
  try {
    std::map<std::string, sdk::ParamValue> given;
    if (auto node = lookup(impl_->given, split_key(where))) {
      if (!node->IsMap()) wrong_type(where, ParamType::Map, *node);
      to_given(*node, schema, where, "", resolve, given);
    }
    sdk::Params params = sdk::validate_params(schema, given, where);
    // Path defaults were written in no config: relative to the default configs directory.
    const std::string defaults_dir = default_config_dir();
    for (const auto& spec : schema.params) {
      if (given.count(spec.name) || !params.has(spec.name)) continue;
      if (spec.type == ParamType::Path)
        params.set(spec.name, resolve_against(defaults_dir, params.get_string(spec.name)));
      if (spec.type == ParamType::PathList) {
        std::vector<std::string> list = params.get_string_list(spec.name);
        for (auto& p : list) p = resolve_against(defaults_dir, p);
        params.set(spec.name, std::move(list));
      }
    }
    return params;
  } catch (const Error& e) {
    throw Error(e.code(), "config " + impl_->source + ": " + e.what());
  }
}

}  // namespace flipper::kernel
