#include "flipper/sdk/params.hpp"

#include <cmath>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

ParamSchema& ParamSchema::add_bool(std::string name, bool def, std::string description) {
  params.push_back({std::move(name),
                    ParamType::Bool,
                    ParamValue{def},
                    false,
                    std::move(description),
                    {},
                    {},
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_int(std::string name, std::int64_t def, std::string description,
                                  std::optional<double> min, std::optional<double> max) {
  params.push_back({std::move(name),
                    ParamType::Int,
                    ParamValue{def},
                    false,
                    std::move(description),
                    min,
                    max,
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_double(std::string name, double def, std::string description,
                                     std::optional<double> min, std::optional<double> max) {
  params.push_back({std::move(name),
                    ParamType::Double,
                    ParamValue{def},
                    false,
                    std::move(description),
                    min,
                    max,
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_string(std::string name, std::string def, std::string description,
                                     std::vector<std::string> one_of) {
  params.push_back({std::move(name),
                    ParamType::String,
                    ParamValue{std::move(def)},
                    false,
                    std::move(description),
                    {},
                    {},
                    std::move(one_of)});
  return *this;
}
ParamSchema& ParamSchema::add_path(std::string name, std::optional<std::string> def,
                                   std::string description, bool required) {
  std::optional<ParamValue> d;
  if (def) d = ParamValue{*def};
  params.push_back(
      {std::move(name), ParamType::Path, d, required, std::move(description), {}, {}, {}});
  return *this;
}
ParamSchema& ParamSchema::add_string_list(std::string name, std::vector<std::string> def,
                                          std::string description) {
  params.push_back({std::move(name),
                    ParamType::StringList,
                    ParamValue{std::move(def)},
                    false,
                    std::move(description),
                    {},
                    {},
                    {}});
  return *this;
}
const ParamSpec* ParamSchema::find(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return &p;
  return nullptr;
}
ParamSchema& ParamSchema::add(ParamSpec spec) {
  params.push_back(std::move(spec));
  return *this;
}
ParamSchema& ParamSchema::add_path_list(std::string name, std::vector<std::string> def,
                                        std::string description) {
  params.push_back({std::move(name),
                    ParamType::PathList,
                    ParamValue{std::move(def)},
                    false,
                    std::move(description),
                    {},
                    {},
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_double_list(std::string name, const std::vector<double>& def,
                                          std::string description) {
  params.push_back({std::move(name),
                    ParamType::DoubleList,
                    ParamValue{def},
                    false,
                    std::move(description),
                    {},
                    {},
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_map(std::string name, std::string description) {
  params.push_back({std::move(name),
                    ParamType::Map,
                    ParamValue{std::vector<std::string>{}},
                    false,
                    std::move(description),
                    {},
                    {},
                    {}});
  return *this;
}
ParamSchema& ParamSchema::add_section(std::string name, std::string description, bool optional) {
  sections.push_back({std::move(name), std::move(description), optional});
  return *this;
}
const ParamSection* ParamSchema::find_section(const std::string& name) const {
  for (const auto& s : sections)
    if (s.name == name) return &s;
  return nullptr;
}
bool ParamSchema::is_section(const std::string& prefix) const {
  for (const auto& p : params)
    if (p.name.size() > prefix.size() && p.name.compare(0, prefix.size(), prefix) == 0 &&
        p.name[prefix.size()] == '.')
      return true;
  return false;
}

const ParamValue& Params::at(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw Error(codes::kBadConfig, "parameter '" + name + "' is not set");
  return it->second;
}
bool Params::get_bool(const std::string& name) const {
  if (auto* v = std::get_if<bool>(&at(name))) return *v;
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not a boolean");
}
std::int64_t Params::get_int(const std::string& name) const {
  if (auto* v = std::get_if<std::int64_t>(&at(name))) return *v;
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not an integer");
}
double Params::get_double(const std::string& name) const {
  const auto& v = at(name);
  if (auto* d = std::get_if<double>(&v)) return *d;
  if (auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not a number");
}
const std::string& Params::get_string(const std::string& name) const {
  if (auto* v = std::get_if<std::string>(&at(name))) return *v;
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not a string");
}
const std::vector<std::string>& Params::get_string_list(const std::string& name) const {
  if (auto* v = std::get_if<std::vector<std::string>>(&at(name))) return *v;
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not a list of strings");
}

std::vector<double> Params::get_double_list(const std::string& name) const {
  if (auto* v = std::get_if<std::vector<double>>(&at(name))) return *v;
  throw Error(codes::kBadConfig, "parameter '" + name + "' is not a list of numbers");
}

std::string to_string(const ParamValue& v) {
  std::ostringstream os;
  if (auto* b = std::get_if<bool>(&v)) {
    os << (*b ? "true" : "false");
  } else if (auto* i = std::get_if<std::int64_t>(&v)) {
    os << *i;
  } else if (auto* d = std::get_if<double>(&v)) {
    os << *d;
  } else if (auto* s = std::get_if<std::string>(&v)) {
    os << '"' << *s << '"';
  } else if (auto* l = std::get_if<std::vector<std::string>>(&v)) {
    os << '[';
    for (std::size_t k = 0; k < l->size(); ++k) os << (k ? ", " : "") << (*l)[k];
    os << ']';
  } else if (auto* n = std::get_if<std::vector<double>>(&v)) {
    os << '[';
    for (std::size_t k = 0; k < n->size(); ++k) os << (k ? ", " : "") << (*n)[k];
    os << ']';
  }
  return os.str();
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
