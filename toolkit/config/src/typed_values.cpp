// Reading a document's maps into the typed values of a schema, and writing them back.
#include "flipper/toolkit/config/typed_values.hpp"

#include <charconv>
#include <cmath>
#include <vector>

#include "flipper/sdk/param_check.hpp"
#include "yaml_tree.hpp"

namespace flipper::toolkit::config {
namespace {

using detail::fail;
using sdk::ParamType;

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

// Empty maps print as `params: {}` on one line (block style would put `{}` on its own line).
void flow_empty_maps(YAML::Node node) {
  if (!node.IsMap()) return;
  if (node.size() == 0) node.SetStyle(YAML::EmitterStyle::Flow);
  for (auto kv : node) flow_empty_maps(kv.second);
}

}  // namespace

void wrong_type(const std::string& key, ParamType type, const YAML::Node& v) {
  fail("config key '" + key + "' must be " + sdk::type_phrase(type) + ", got " + scalar_text(v));
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

std::map<std::string, sdk::ParamValue> typed_values(const YAML::Node& node,
                                                    const sdk::ParamSchema& schema,
                                                    const std::string& where, const PathFn& path) {
  std::map<std::string, sdk::ParamValue> given;
  to_given(node, schema, where, "", path, given);
  return given;
}

std::string dump_values(const sdk::ParamSchema& schema, const sdk::Params& values,
                        const YAML::Node& tree) {
  // A plugin's params as written: its own schema is the loader's business.
  YAML::Node copy(YAML::NodeType::Map);
  for (const auto& spec : schema.params) {
    if (!values.has(spec.name)) continue;
    const auto segs = detail::split_key(spec.name);
    const auto written = detail::lookup(tree, segs);
    YAML::Node value = spec.type != ParamType::Map ? yaml_of(values.values().at(spec.name))
                       : written                   ? YAML::Clone(*written)
                                                   : YAML::Node(YAML::NodeType::Map);
    detail::set_path(copy, segs, 0, value);
  }
  flow_empty_maps(copy);
  YAML::Emitter out;
  out.SetSeqFormat(YAML::Flow);
  out << copy;
  return std::string(out.c_str()) + "\n";
}

}  // namespace flipper::toolkit::config
