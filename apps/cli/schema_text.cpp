#include "schema_text.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <sstream>

#include <sys/ioctl.h>
#include <unistd.h>
#include <cstdlib>

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

std::string default_text(const sdk::ParamSpec& p, const sdk::ParamSchema* schema) {
  if (p.type == sdk::ParamType::Map) return "{}";
  if (p.default_value) return sdk::to_string(*p.default_value);
  if (!p.required) return "(none)";
  // A key required only when its optional section is given ("rewriter.plugin") is not required.
  const std::string section = p.name.substr(0, p.name.find('.'));
  const sdk::ParamSection* s =
      schema != nullptr && section != p.name ? schema->find_section(section) : nullptr;
  return s != nullptr && s->optional ? "(none; needed with " + section + ")" : "(required)";
}

std::vector<const sdk::ParamSpec*> specs_under(const sdk::ParamSchema& schema,
                                               const std::string& prefix) {
  std::vector<const sdk::ParamSpec*> out;
  for (const auto& p : schema.params)
    if (below(p.name, prefix)) out.push_back(&p);
  return out;
}

std::size_t terminal_width() {
  winsize ws{};
  if (isatty(STDOUT_FILENO) && ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 40)
    return ws.ws_col;
  if (const char* columns = std::getenv("COLUMNS")) {
    const long n = std::strtol(columns, nullptr, 10);
    if (n >= 40 && n <= 1000) return static_cast<std::size_t>(n);
  }
  return 100;
}

std::vector<std::string> wrap_words(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream words(text);
  for (std::string w; words >> w;) {
    // A word longer than the width (a path) is cut after a '/' where it can be, else anywhere.
    while (w.size() > width && width > 1) {
      if (!line.empty()) {
        lines.push_back(line);
        line.clear();
      }
      std::size_t cut = w.rfind('/', width - 1);
      cut = cut == std::string::npos || cut == 0 ? width : cut + 1;
      lines.push_back(w.substr(0, cut));
      w.erase(0, cut);
    }
    if (!line.empty() && line.size() + 1 + w.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + w;
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

std::string text_table(const std::vector<const sdk::ParamSpec*>& specs, const std::string& header,
                       const std::string& indent, const TableOptions& options) {
  std::vector<std::array<std::string, 5>> rows = {
      {header, "TYPE", "DEFAULT", "ALLOWED", "DESCRIPTION"}};
  for (const auto* s : specs)
    rows.push_back({options.name_prefix + s->name, sdk::to_string(s->type),
                    default_text(*s, options.schema), allowed_text(*s), s->description});
  // Name and type keep their width; a long default or list of allowed values wraps within 24
  // columns; the description wraps within what is left of the width (at least 24 columns).
  constexpr std::size_t kValueColumn = 24;
  std::array<std::size_t, 5> w{};
  for (const auto& r : rows)
    for (std::size_t i = 0; i < 4; ++i) w[i] = std::max(w[i], r[i].size());
  w[2] = std::min(w[2], kValueColumn);
  w[3] = std::min(w[3], kValueColumn);
  std::size_t lead = indent.size();
  for (std::size_t i = 0; i < 4; ++i) lead += w[i] + 2;
  w[4] = options.width > lead + kValueColumn ? options.width - lead : kValueColumn;
  std::string out;
  for (const auto& r : rows) {
    std::array<std::vector<std::string>, 5> cells;
    std::size_t height = 1;
    for (std::size_t i = 0; i < 5; ++i) {
      cells[i] = i < 2 ? std::vector<std::string>{r[i]} : wrap_words(r[i], w[i]);
      height = std::max(height, cells[i].size());
    }
    for (std::size_t line = 0; line < height; ++line) {
      std::string text = indent;
      for (std::size_t i = 0; i < 5; ++i) {
        const std::string part = line < cells[i].size() ? cells[i][line] : "";
        text += part;
        if (i < 4) text += std::string(w[i] + 2 > part.size() ? w[i] + 2 - part.size() : 1, ' ');
      }
      while (!text.empty() && text.back() == ' ') text.pop_back();
      out += text + "\n";
    }
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
    out += "| `" + p.name + "` | " + sdk::to_string(p.type) + " | `" +
           cell(default_text(p, &schema)) + "` | " + cell(allowed_text(p)) + " | " +
           cell(p.description) + " |\n";
  }
  return out;
}

}  // namespace flipper::cli
