// Config loading: the document (toolkit/config: the file or the embedded default over the files
// it `extends`, then --set overrides, nulls dropped) read into typed values and validated against
// the installed schema with the SDK's engine, which fills defaults. Plugin params go through the
// same two steps against the plugin's schema.
#include "flipper/kernel/config.hpp"

#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/toolkit/config/document.hpp"
#include "flipper/toolkit/config/typed_values.hpp"

namespace flipper::kernel {
namespace detail {
extern const char* const kEmbeddedDefaultConfig;  // generated from configs/default.yaml
}

namespace fs = std::filesystem;
using sdk::Error;
using sdk::ParamType;
using toolkit::config::ConfigDocument;
using toolkit::config::resolve_against;
namespace codes = sdk::codes;

struct Config::Impl {
  ConfigDocument doc;  // the merged tree as written and who wrote each key; plugin params read it
  sdk::Params values;  // the kernel keys, validated, defaults filled; never mutated once shared
};

namespace {

constexpr const char* kEmbeddedSource = "<embedded default>";

[[noreturn]] void fail(const std::string& message) {
  throw Error(codes::kBadConfig, message);
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

// What the document needs of the schema: the keys a --set gives as text, the plugin sections,
// and the directory of the embedded default, which a key nobody wrote resolves against.
toolkit::config::DocumentRules document_rules() {
  const auto text_key = [](const std::string& key) {
    const sdk::ParamSpec* spec = Config::schema().find(key);
    return spec != nullptr && (spec->type == ParamType::String || spec->type == ParamType::Path);
  };
  return {text_key, Config::plugin_sections(), default_config_dir()};
}

// The kernel keys of a document, validated with defaults filled; a message names the file that
// wrote the key it is about.
Config bind(ConfigDocument doc) {
  sdk::Params values;
  try {
    const YAML::Node& root = doc.tree();
    if (!root.IsMap())
      fail("a config must be a YAML map of sections, got " + toolkit::config::scalar_text(root));
    const toolkit::config::PathFn as_written = [](const std::string&, const std::string& text) {
      return text;
    };
    values = sdk::validate_params(
        Config::schema(), toolkit::config::typed_values(root, Config::schema(), "", as_written),
        "");
  } catch (const Error& e) {
    throw Error(e.code(), "config " + doc.where_written(e.what()) + ": " + e.what());
  }
  return Config(std::make_shared<Config::Impl>(Config::Impl{std::move(doc), std::move(values)}));
}

// A key below a plugin section's params (not a kernel key): read from the tree as written.
YAML::Node node_at(const Config::Impl& impl, const std::string& key) {
  auto v = impl.doc.find(key);
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
  if (!file)
    return bind(ConfigDocument::parse(detail::kEmbeddedDefaultConfig, kEmbeddedSource,
                                      default_config_dir(), overrides, document_rules()));
  return bind(ConfigDocument::read(*file, overrides, document_rules()));
}

Config Config::embedded_default() {
  return load(std::nullopt, {});
}

const std::string& Config::source() const {
  return impl_->doc.source();
}
const std::string& Config::base_dir() const {
  return impl_->doc.base_dir();
}

std::string Config::resolve_path(const std::string& path) const {
  return resolve_against(impl_->doc.base_dir(), path);
}

bool Config::written(const std::string& key) const {
  return impl_->doc.written(key);
}

std::string Config::resolve_path_of(const std::string& key, const std::string& path) const {
  return impl_->doc.resolve_path_of(key, path);
}

std::string Config::path_origin(const std::string& key) const {
  const sdk::ParamSpec* spec = schema().find(key);
  const auto node = impl_->doc.find(key);
  const std::string value =
      spec != nullptr && spec->type == ParamType::Path && impl_->values.has(key)
          ? " '" + impl_->values.get_string(key) + "'"
      : node && node->IsScalar() ? " '" + node->Scalar() + "'"
                                 : "";
  return impl_->doc.path_origin(key, value);
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
  return impl_->doc.find(key).has_value();
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
  const auto v = n.IsScalar() ? toolkit::config::parse_int(n.Scalar()) : std::nullopt;
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
  *this = bind(impl_->doc.with(assignment));
}

std::string Config::dump() const {
  return toolkit::config::dump_values(schema(), impl_->values, impl_->doc.tree());
}

const std::vector<std::string>& Config::plugin_sections() {
  static const std::vector<std::string> kSections = {"world",  "planner",  "parser",
                                                     "scorer", "rewriter", "similarity"};
  return kSections;
}

sdk::Params Config::plugin_params(const std::string& section,
                                  const sdk::ParamSchema& schema) const {
  const std::string where = section + ".params";
  const toolkit::config::PathFn resolve = [this](const std::string& key, const std::string& text) {
    return resolve_path_of(key, text);
  };
  try {
    std::map<std::string, sdk::ParamValue> given;
    if (auto node = impl_->doc.find(where)) {
      if (!node->IsMap()) toolkit::config::wrong_type(where, ParamType::Map, *node);
      given = toolkit::config::typed_values(*node, schema, where, resolve);
    }
    sdk::Params params = sdk::validate_params(schema, given, where);
    // Path defaults were written in no config: relative to the default configs directory.
    const std::string& defaults_dir = impl_->doc.rules().defaults_dir;
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
    throw Error(e.code(), "config " + impl_->doc.source() + ": " + e.what());
  }
}

}  // namespace flipper::kernel
