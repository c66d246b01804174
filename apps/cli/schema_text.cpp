#include "schema_text.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <sstream>

#include "flipper/sdk/param_check.hpp"

namespace flipper::cli {
namespace {

std::string number(double v, sdk::ParamType type) {
  std::ostringstream s;
  if (type == sdk::ParamType::Int)
    s << static_cast<std::int64_t>(v);
  else
    s << v;
  return s.str();
}

bool below(const std::string& name, const std::string& prefix) {
  return prefix.empty() || name == prefix ||
         (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
          name[prefix.size()] == '.');
}

// Markdown cell text: a '|' would end the cell.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

std::string allowed_text(const sdk::ParamSpec& p) {
  if (p.min && p.max) return "[" + number(*p.min, p.type) + ", " + number(*p.max, p.type) + "]";
  if (p.min) return ">= " + number(*p.min, p.type);
  if (p.max) return "<= " + number(*p.max, p.type);
  if (!p.one_of.empty()) {
    std::string out = "one of: ";
    for (std::size_t i = 0; i < p.one_of.size(); ++i) out += (i ? ", " : "") + p.one_of[i];
    return out;
  }
  return "-";
}

std::string default_text(const sdk::ParamSpec& p) {
  if (p.type == sdk::ParamType::Map) return "{}";
  if (p.default_value) return sdk::to_string(*p.default_value);
  return p.required ? "(required)" : "(none)";
}

std::vector<const sdk::ParamSpec*> specs_under(const sdk::ParamSchema& schema,
                                               const std::string& prefix) {
  std::vector<const sdk::ParamSpec*> out;
  for (const auto& p : schema.params)
    if (below(p.name, prefix)) out.push_back(&p);
  return out;
}

std::string text_table(const std::vector<const sdk::ParamSpec*>& specs, const std::string& header,
                       const std::string& indent) {
  std::vector<std::array<std::string, 5>> rows = {
      {header, "TYPE", "DEFAULT", "ALLOWED", "DESCRIPTION"}};
  for (const auto* s : specs)
    rows.push_back(
        {s->name, sdk::to_string(s->type), default_text(*s), allowed_text(*s), s->description});
  std::array<std::size_t, 4> w{};
  for (const auto& r : rows)
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = std::max(w[i], r[i].size());
  std::string out;
  for (const auto& r : rows) {
    out += indent;
    for (std::size_t i = 0; i < w.size(); ++i)
      out += r[i] + std::string(w[i] + 2 - r[i].size(), ' ');
    out += r[4] + "\n";
  }
  return out;
}

std::string markdown_table(const sdk::ParamSchema& schema) {
  std::string out = "| Key | Type | Default | Allowed | Description |\n|---|---|---|---|---|\n";
  std::vector<std::string> done;
  for (const auto& p : schema.params) {
    const std::string section = p.name.substr(0, p.name.find('.'));
    const sdk::ParamSection* s = schema.find_section(section);
    if (s != nullptr && std::find(done.begin(), done.end(), section) == done.end()) {
      done.push_back(section);
      out += "| **`" + section + "`** | section | | " + (s->optional ? "optional" : "") + " | " +
             cell(s->description) + " |\n";
    }
    out += "| `" + p.name + "` | " + sdk::to_string(p.type) + " | `" + cell(default_text(p)) +
           "` | " + cell(allowed_text(p)) + " | " + cell(p.description) + " |\n";
  }
  return out;
}

}  // namespace flipper::cli
