#pragma once
/// @file params.hpp
/// Declarative parameter schemas and the typed view a plugin receives. The kernel validates the
/// YAML config against a plugin's schema before constructing it (unknown keys, wrong types and
/// out-of-range values are errors), fills in defaults, and hands the plugin a `Params`. No
/// yaml-cpp type appears here, so the SDK ABI does not depend on it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace v1 {

enum class ParamType { Bool, Int, Double, String, StringList, Path };

/// A parameter value. `Path` values are stored as strings already resolved against the config
/// file's directory.
using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::vector<std::string>>;

/// One declared parameter, in the style of BehaviorTree.CPP ports / MoveIt parameter YAML.
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::String;
  std::optional<ParamValue> default_value;  ///< absent + !required => the key is simply absent
  bool required = false;
  std::string description;
  std::optional<double> min;           ///< numeric lower bound (inclusive)
  std::optional<double> max;           ///< numeric upper bound (inclusive)
  std::vector<std::string> one_of;     ///< allowed string values (empty: any)
};

/// A plugin's full schema.
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
};

/// The validated parameters a plugin is constructed with: every declared parameter with a
/// default is present; typed getters throw flipper::sdk::Error(bad_config) on a type mismatch.
class FLIPPER_SDK_API Params {
 public:
  Params() = default;
  explicit Params(std::map<std::string, ParamValue> values) : values_(std::move(values)) {}

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  bool get_bool(const std::string& name) const;
  std::int64_t get_int(const std::string& name) const;
  double get_double(const std::string& name) const;  ///< an Int value converts
  const std::string& get_string(const std::string& name) const;  ///< String or Path
  const std::vector<std::string>& get_string_list(const std::string& name) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }
  void set(const std::string& name, ParamValue v) { values_[name] = std::move(v); }

 private:
  const ParamValue& at(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

/// Renders a value for listings and run records (`true`, `42`, `0.5`, `"text"`, `[a, b]`).
FLIPPER_SDK_API std::string to_string(const ParamValue& v);

}  // namespace v1
}  // namespace flipper::sdk
