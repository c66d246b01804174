#include "flipper/sdk/param_check.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace {

// Optimal string alignment distance: insertions, deletions, substitutions and transpositions
// of two neighbours ("mvoe" -> "move" is one edit), each costing 1.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> before(b.size() + 1), prev(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      row[j] =
          std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, prev);
    std::swap(prev, row);
  }
  return prev[b.size()];
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
    case ParamType::PathList:
    case ParamType::Map:
      return std::holds_alternative<std::vector<std::string>>(v);
    case ParamType::DoubleList:
      return std::holds_alternative<std::vector<double>>(v);
  }
  return false;
}

// A bound as written: integers without exponent (1099511627776, not 1.09951e+12).
std::string num(double x, ParamType type) {
  std::ostringstream os;
  if (type == ParamType::Int && std::abs(x) < 9.2e18)
    os << static_cast<std::int64_t>(x);
  else
    os << x;
  return os.str();
}

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

bool below(const std::string& name, const std::string& prefix) {
  return prefix.empty() ||
         (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
          name[prefix.size()] == '.');
}

// Names one level below `prefix` ("" for the top), in declaration order.
std::vector<std::string> child_names(const ParamSchema& schema, const std::string& prefix) {
  std::vector<std::string> out;
  const std::size_t skip = prefix.empty() ? 0 : prefix.size() + 1;
  for (const auto& p : schema.params) {
    if (!below(p.name, prefix) || is_retired(p)) continue;
    const std::string rest = p.name.substr(skip);
    const std::string name = rest.substr(0, rest.find('.'));
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  return out;
}

// A value as a message shows it: text in single quotes, so an empty one is visible.
std::string shown(const ParamValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return "'" + *s + "'";
  return to_string(v);
}

[[noreturn]] void fail(const std::string& message) {
  throw Error(codes::kBadConfig, message);
}

// "unknown config key 'a.b' (did you mean 'a.c'?); keys in 'a': c, d": the key is cut at the
// first name no section declares, and hints come from its siblings only.
[[noreturn]] void fail_unknown(const ParamSchema& schema, const std::string& name,
                               const std::string& prefix, const std::string& where) {
  std::string section;
  std::size_t start = 0;
  for (std::size_t dot; (dot = name.find('.', start)) != std::string::npos; start = dot + 1) {
    const std::string longer = name.substr(0, dot);
    if (!schema.is_section(longer)) break;
    section = longer;
  }
  const std::string word = name.substr(start, name.find('.', start) - start);
  const std::string inner = section.empty() ? "" : section + ".";
  const std::vector<std::string> siblings = child_names(schema, section);
  std::string hint = did_you_mean(word, siblings);
  if (!hint.empty()) {
    const std::string lead = " (did you mean '";
    hint = lead + prefix + inner + hint.substr(lead.size());
  }
  const std::string place = section.empty() ? where : prefix + section;
  std::string known;
  if (siblings.empty())
    known = "; '" + where + "' takes no keys";
  else if (place.empty())
    known = "; top-level keys: " + join(siblings);
  else
    known = "; keys in '" + place + "': " + join(siblings);
  fail("unknown config key '" + prefix + inner + word + "'" + hint + known);
}

// The optional section `name` lies in, if any.
const ParamSection* optional_section_of(const ParamSchema& schema, const std::string& name) {
  for (const auto& s : schema.sections)
    if (s.optional && below(name, s.name)) return &s;
  return nullptr;
}

bool section_given(const std::map<std::string, ParamValue>& given, const std::string& section) {
  for (const auto& kv : given)
    if (below(kv.first, section)) return true;
  return false;
}

}  // namespace

const char* type_phrase(ParamType type) {
  switch (type) {
    case ParamType::Bool:
      return "a boolean (true/false)";
    case ParamType::Int:
      return "an integer";
    case ParamType::Double:
      return "a number";
    case ParamType::String:
      return "a string";
    case ParamType::StringList:
      return "a list of strings";
    case ParamType::Path:
      return "a path";
    case ParamType::PathList:
      return "a list of paths";
    case ParamType::DoubleList:
      return "a list of numbers";
    case ParamType::Map:
      return "a map";
  }
  return "a value";
}

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
    case ParamType::PathList:
      return "path list";
    case ParamType::DoubleList:
      return "double list";
    case ParamType::Map:
      return "map";
  }
  return "unknown";
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  // About one edit per three letters, at least one: catches typos ("vist", "mvoe", "sesion"),
  // not unrelated words. A one-letter word has no likely intent; a two-letter one must keep its
  // first letter ("kk" -> "k", but "go" is neither "to" nor "+"). With these rules a word of
  // letters is never offered punctuation: the grammar's symbols are one or two characters long.
  if (word.size() < 2) return "";
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  const std::string* best = nullptr;
  std::size_t best_d = 0;
  for (const auto& c : candidates) {
    if (word.size() == 2 && (c.empty() || c[0] != word[0])) continue;
    const std::size_t d = edit_distance(word, c);
    if (d == 0 || d > limit) continue;
    if (best == nullptr || d < best_d) {
      best = &c;
      best_d = d;
    }
  }
  if (best == nullptr) return "";
  return " (did you mean '" + *best + "'?)";
}

Params validate_params(const ParamSchema& schema, const std::map<std::string, ParamValue>& given,
                       const std::string& where) {
  const std::string prefix = where.empty() ? "" : where + ".";
  for (const auto& kv : given) {
    const ParamSpec* spec = schema.find(kv.first);
    if (spec == nullptr) fail_unknown(schema, kv.first, prefix, where);
    if (is_retired(*spec)) fail("config key '" + prefix + kv.first + "' is " + spec->description);
  }
  Params out;
  for (const auto& spec : schema.params) {
    const std::string key = prefix + spec.name;
    const ParamSection* optional = optional_section_of(schema, spec.name);
    if (optional != nullptr && !section_given(given, optional->name)) continue;
    auto it = given.find(spec.name);
    if (it == given.end()) {
      if (spec.required && optional != nullptr)
        fail("missing required config key '" + key + "': the optional section '" + prefix +
             optional->name + "' is given, so it needs one");
      if (spec.required) fail("missing required config key '" + key + "'");
      if (spec.default_value) out.set(spec.name, *spec.default_value);
      continue;
    }
    const ParamValue& v = it->second;
    if (!type_matches(spec.type, v))
      fail("config key '" + key + "' must be " + type_phrase(spec.type) + ", got " + shown(v));
    if (spec.type == ParamType::Int || spec.type == ParamType::Double) {
      const double x = std::holds_alternative<double>(v)
                           ? std::get<double>(v)
                           : static_cast<double>(std::get<std::int64_t>(v));
      if ((spec.min && x < *spec.min) || (spec.max && x > *spec.max))
        fail("config key '" + key + "' = " + to_string(v) + " is out of range [" +
             (spec.min ? num(*spec.min, spec.type) : "-inf") + ", " +
             (spec.max ? num(*spec.max, spec.type) : "inf") + "]");
      if (spec.type == ParamType::Double) {
        out.set(spec.name, x);  // store Int given for a Double as a double
        continue;
      }
    }
    if (spec.type == ParamType::String && !spec.one_of.empty() &&
        std::find(spec.one_of.begin(), spec.one_of.end(), std::get<std::string>(v)) ==
            spec.one_of.end())
      fail("config key '" + key + "' = " + shown(v) + " must be one of: " + join(spec.one_of) +
           did_you_mean(std::get<std::string>(v), spec.one_of));
    out.set(spec.name, v);
  }
  return out;
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
