#pragma once
/// @file params.hpp
/// Declarative parameter schemas and the typed view a plugin receives. The kernel validates the
/// YAML config against a plugin's schema before constructing it (unknown keys, wrong types and
/// out-of-range values are errors), fills in defaults, and hands the plugin a `Params`. The
/// kernel declares its own config keys with the same schema (dotted names, sections), so plugin
/// params and kernel keys are checked by one engine with one wording (param_check.hpp). No
/// yaml-cpp type appears here, so the SDK ABI does not depend on it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Values are only ever appended (PathList, DoubleList and Map came later): an older plugin never
/// declares the new ones, so the values it knows keep their numbers (docs/sdk-migration.md).
enum class ParamType { Bool, Int, Double, String, StringList, Path, PathList, DoubleList, Map };

/// A parameter value. `Path` values are stored as strings already resolved against the config
/// file's directory; PathList holds the resolved paths, Map the key names of an opaque map another
/// schema validates (e.g. a plugin section's `params`), DoubleList the numbers themselves (the
/// last alternative; read them with Params::get_double_list).
using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::vector<std::string>,
                                std::vector<double>>;

/// What a ParamSpec's `flags` may hold, one bit each.
enum class ParamFlag : std::uint32_t {
  /// A key that no longer exists (ParamSchema::add_retired): a config that gives it is refused.
  retired = 1u << 0,
};

/// One declared parameter, in the style of BehaviorTree.CPP ports / MoveIt parameter YAML.
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::String;
  std::optional<ParamValue> default_value;  ///< absent + !required => the key is simply absent
  bool required = false;
  std::string description;
  std::optional<double> min;        ///< numeric lower bound (inclusive)
  std::optional<double> max;        ///< numeric upper bound (inclusive)
  std::vector<std::string> one_of;  ///< allowed string values (empty: any)
  std::uint32_t flags = 0;          ///< ParamFlag bits
  bool has(ParamFlag f) const { return (flags & static_cast<std::uint32_t>(f)) != 0; }
};

/// A group of dotted names: the parameters "a.x" and "a.y" lie in section "a". A section needs no
/// declaration; declaring one documents it and may make it optional: then its parameters get no
/// defaults and `required` applies only when the config gives some key of the section.
struct ParamSection {
  std::string name;
  std::string description;
  bool optional = false;
};

/// A plugin's full schema (or the kernel's, kernel/config).
struct FLIPPER_SDK_API ParamSchema {
  std::vector<ParamSpec> params;

  /// Fluent helpers for plugin authors.
  ParamSchema& add_bool(std::string name, bool def, std::string description);
  ParamSchema& add_int(std::string name, std::int64_t def, std::string description,
                       std::optional<double> min = {}, std::optional<double> max = {});
  ParamSchema& add_double(std::string name, double def, std::string description,
                          std::optional<double> min = {}, std::optional<double> max = {});
  ParamSchema& add_string(std::string name, std::string def, std::string description,
                          std::vector<std::string> one_of = {});
  /// A filesystem path; relative values are resolved against the config file's directory.
  ParamSchema& add_path(std::string name, std::optional<std::string> def, std::string description,
                        bool required = false);
  ParamSchema& add_string_list(std::string name, std::vector<std::string> def,
                               std::string description);
  const ParamSpec* find(const std::string& name) const;

  // Added after `params` (new exported functions and a trailing member: an older plugin's
  // describe() assigns `params` only and loads unchanged; docs/sdk-migration.md).
  /// Any spec, e.g. a required string without a default.
  ParamSchema& add(ParamSpec spec);
  ParamSchema& add_path_list(std::string name, std::vector<std::string> def,
                             std::string description);
  ParamSchema& add_double_list(std::string name, const std::vector<double>& def,
                               std::string description);
  /// An opaque map (validated elsewhere, e.g. against a plugin's own schema); default `{}`.
  ParamSchema& add_map(std::string name, std::string description);
  ParamSchema& add_section(std::string name, std::string description, bool optional = false);
  const ParamSection* find_section(const std::string& name) const;
  /// Whether some parameter lies below `prefix` ("a" for "a.x").
  bool is_section(const std::string& prefix) const;

  std::vector<ParamSection> sections;

  /// A key that no longer exists: a config that still gives it is refused (bad_config) with
  /// "config key '<key>' is retired: <hint>" rather than as an unknown key, so that the hint can
  /// say what replaced it. It has no default, never reaches the plugin, and no "did you mean"
  /// suggests it. Flagged ParamFlag::retired; its description reads "retired: <hint>".
  ParamSchema& add_retired(std::string name, const std::string& hint) {
    ParamSpec spec;
    spec.name = std::move(name);
    spec.description = "retired: " + hint;
    spec.flags = static_cast<std::uint32_t>(ParamFlag::retired);
    params.push_back(std::move(spec));
    return *this;
  }
};

/// Whether `spec` was declared with ParamSchema::add_retired().
inline bool is_retired(const ParamSpec& spec) {
  return spec.has(ParamFlag::retired);
}

/// The validated parameters a plugin is constructed with: every declared parameter with a
/// default is present; typed getters throw flipper::sdk::Error(bad_config) on a type mismatch.
class FLIPPER_SDK_API Params {
 public:
  Params() = default;
  explicit Params(std::map<std::string, ParamValue> values) : values_(std::move(values)) {}

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  bool get_bool(const std::string& name) const;
  std::int64_t get_int(const std::string& name) const;
  double get_double(const std::string& name) const;              ///< an Int value converts
  const std::string& get_string(const std::string& name) const;  ///< String or Path
  const std::vector<std::string>& get_string_list(const std::string& name) const;
  /// A DoubleList.
  std::vector<double> get_double_list(const std::string& name) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }
  void set(const std::string& name, ParamValue v) { values_[name] = std::move(v); }

 private:
  const ParamValue& at(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

/// Renders a value for listings and run records (`true`, `42`, `0.5`, `"text"`, `[a, b]`).
FLIPPER_SDK_API std::string to_string(const ParamValue& v);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
