// The language guide (docs/language.md, embedded at build time) as the repl shows it.
#include <algorithm>
#include <sstream>

#include "flipper/repl/repl.hpp"

namespace flipper::repl {
namespace detail {
extern const char* const kLanguageGuide;
}

std::vector<GuideExample> guide_examples() {
  std::vector<GuideExample> out;
  std::istringstream in(detail::kLanguageGuide);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("<!-- language-examples", 0) == 0) inside = true;
    if (line.rfind("<!-- /language-examples", 0) == 0) inside = false;
    if (!inside || line.rfind("| ", 0) != 0) continue;
    // | construct | `example` | result |
    std::vector<std::string> cells;
    std::size_t start = 1;
    for (std::size_t bar; (bar = line.find(" |", start)) != std::string::npos; start = bar + 2)
      cells.push_back(line.substr(start + 1, bar - start - 1));
    if (cells.size() != 3 || cells[1].size() < 2 || cells[1].front() != '`') continue;
    out.push_back({cells[0], cells[1].substr(1, cells[1].size() - 2), cells[2]});
  }
  return out;
}

std::string examples_text() {
  std::ostringstream out;
  out << "Examples from docs/language.md (the robot starts at [2,4] on the study map):\n";
  for (const auto& e : guide_examples())
    out << "  " << e.example << "\n      " << e.construct << ": " << e.result << "\n";
  out << "Type one to see its readings; docs/language.md explains each construct.\n";
  return out.str();
}

std::string guide_help_text() {
  const auto examples = guide_examples();
  std::vector<std::string> names;
  std::size_t width = 0;
  for (const auto& e : examples) {
    std::string name;  // without the markdown's backticks
    for (char c : e.construct)
      if (c != '`') name += c;
    width = std::max(width, name.size());
    names.push_back(std::move(name));
  }
  std::ostringstream out;
  out << "The language (docs/language.md; :examples shows what each example does):\n";
  for (std::size_t i = 0; i < examples.size(); ++i)
    out << "  " << names[i] << std::string(width - names[i].size() + 3, ' ') << examples[i].example
        << '\n';
  out << "docs/language.md sections: ";
  std::istringstream in(detail::kLanguageGuide);
  bool first = true;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) != 0) continue;
    out << (first ? "" : " \u00b7 ") << line.substr(3);
    first = false;
  }
  out << "\n";
  return out.str();
}

}  // namespace flipper::repl
