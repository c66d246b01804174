#include "flipper/sdk/param_check.hpp"

#include <algorithm>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace v1 {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

bool type_matches(ParamType type, const ParamValue& v) {
  switch (type) {
    case ParamType::Bool:
      return std::holds_alternative<bool>(v);
    case ParamType::Int:
      return std::holds_alternative<std::int64_t>(v);
    case ParamType::Double:
      return std::holds_alternative<double>(v) || std::holds_alternative<std::int64_t>(v);
    case ParamType::String:
    case ParamType::Path:
      return std::holds_alternative<std::string>(v);
    case ParamType::StringList:
      return std::holds_alternative<std::vector<std::string>>(v);
  }
  return false;
}

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

}  // namespace

const char* to_string(ParamType type) {
  switch (type) {
    case ParamType::Bool:
      return "bool";
    case ParamType::Int:
      return "int";
    case ParamType::Double:
      return "double";
    case ParamType::String:
      return "string";
    case ParamType::StringList:
      return "string list";
    case ParamType::Path:
      return "path";
  }
  return "unknown";
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string* best = nullptr;
  std::size_t best_d = 0;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (best == nullptr || d < best_d) {
      best = &c;
      best_d = d;
    }
  }
  // Allow about one edit per three letters, at least two: catches typos, not unrelated words.
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  if (best == nullptr || best_d > limit) return "";
  return " (did you mean '" + *best + "'?)";
}

Params validate_params(const ParamSchema& schema, const std::map<std::string, ParamValue>& given,
                       const std::string& where) {
  const std::string prefix = where.empty() ? "" : where + ".";
  std::vector<std::string> names;
  for (const auto& spec : schema.params) names.push_back(spec.name);
  for (const auto& [key, value] : given) {
    if (schema.find(key) != nullptr) continue;
    throw Error(codes::kBadConfig,
                "unknown parameter '" + prefix + key + "'" + did_you_mean(key, names) +
                    "; known parameters: " + (names.empty() ? "none" : join(names)));
  }
  Params out;
  for (const auto& spec : schema.params) {
    const std::string key = prefix + spec.name;
    auto it = given.find(spec.name);
    if (it == given.end()) {
      if (spec.required) throw Error(codes::kBadConfig, "missing required parameter '" + key + "'");
      if (spec.default_value) out.set(spec.name, *spec.default_value);
      continue;
    }
    const ParamValue& v = it->second;
    if (!type_matches(spec.type, v))
      throw Error(codes::kBadConfig, "parameter '" + key + "' must be a " + to_string(spec.type) +
                                         ", got " + to_string(v));
    if (spec.type == ParamType::Int || spec.type == ParamType::Double) {
      const double x = std::holds_alternative<double>(v)
                           ? std::get<double>(v)
                           : static_cast<double>(std::get<std::int64_t>(v));
      if ((spec.min && x < *spec.min) || (spec.max && x > *spec.max)) {
        std::ostringstream os;
        os << "parameter '" << key << "' = " << to_string(v) << " is out of range ["
           << (spec.min ? num(*spec.min) : "-inf") << ", " << (spec.max ? num(*spec.max) : "inf")
           << "]";
        throw Error(codes::kBadConfig, os.str());
      }
      if (spec.type == ParamType::Double) {
        out.set(spec.name, x);  // store Int given for a Double as a double
        continue;
      }
    }
    if (spec.type == ParamType::String && !spec.one_of.empty() &&
        std::find(spec.one_of.begin(), spec.one_of.end(), std::get<std::string>(v)) ==
            spec.one_of.end())
      throw Error(codes::kBadConfig, "parameter '" + key + "' = " + to_string(v) +
                                         " must be one of: " + join(spec.one_of) +
                                         did_you_mean(std::get<std::string>(v), spec.one_of));
    out.set(spec.name, v);
  }
  return out;
}

}  // namespace v1
}  // namespace flipper::sdk
