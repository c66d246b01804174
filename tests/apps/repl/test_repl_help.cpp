// `:help` lists the language from docs/language.md: every construct of the guide's example table
// (with its example) and every section title, in the guide's order, and nothing else. The guide
// is parsed here from the source tree, independently of the repl's embedded copy.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tmux_repl.hpp"

namespace {

struct Row {
  std::string construct;
  std::string example;
};

std::string without_backticks(const std::string& s) {
  std::string out;
  for (char c : s)
    if (c != '`') out += c;
  return out;
}

// The guide's table rows: "| construct | `example` | result |" between the example markers.
void read_guide(std::vector<Row>& rows, std::vector<std::string>& sections) {
  std::ifstream in(FLIPPER_SOURCE_DIR "/docs/language.md");
  REQUIRE(in.good());
  bool table = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0) sections.push_back(line.substr(3));
    if (line.rfind("<!-- language-examples", 0) == 0) table = true;
    if (line.rfind("<!-- /language-examples", 0) == 0) table = false;
    if (!table || line.rfind("| ", 0) != 0 || line.rfind("| Construct |", 0) == 0) continue;
    const auto first = line.find(" | ", 2);
    const auto second = line.find(" | ", first + 3);
    REQUIRE(second != std::string::npos);
    rows.push_back({without_backticks(line.substr(2, first - 2)),
                    without_backticks(line.substr(first + 3, second - first - 3))});
  }
}

// `:help`'s language part: "  construct   example" lines after "The language (...", then
// "docs/language.md sections: A · B · C".
void read_help(const std::string& help, std::vector<Row>& rows,
               std::vector<std::string>& sections) {
  std::istringstream in(help);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("The language (docs/language.md", 0) == 0) {
      inside = true;
      continue;
    }
    const std::string prefix = "docs/language.md sections: ";
    if (line.rfind(prefix, 0) == 0) {
      std::string rest = line.substr(prefix.size());
      const std::string dot = " \u00b7 ";
      for (std::size_t at; (at = rest.find(dot)) != std::string::npos;
           rest.erase(0, at + dot.size()))
        sections.push_back(rest.substr(0, at));
      sections.push_back(rest);
      inside = false;
    }
    if (!inside || line.rfind("  ", 0) != 0) continue;
    const auto gap = line.find("   ", 2);
    REQUIRE(gap != std::string::npos);
    const auto example = line.find_first_not_of(' ', gap);
    rows.push_back({line.substr(2, gap - 2), line.substr(example)});
  }
}

}  // namespace

TEST_CASE("repl :help lists every construct and section of docs/language.md and nothing else",
          "[repl][help]") {
  std::vector<Row> guide_rows, help_rows;
  std::vector<std::string> guide_sections, help_sections;
  read_guide(guide_rows, guide_sections);
  REQUIRE(guide_rows.size() == 30);  // the guide's table as written (a row added: update this)
  REQUIRE(guide_sections.size() == 5);

  const std::string help = flipper::testsupport::shell_output(
      "printf ':help\\n' | " +
      flipper::testsupport::repl_command(flipper::testsupport::repl_temp_file("help-hist")));
  INFO(help);
  CHECK_THAT(help, Catch::Contains("  :define HEAD   teach HEAD"));
  read_help(help, help_rows, help_sections);

  REQUIRE(help_rows.size() == guide_rows.size());
  for (std::size_t i = 0; i < guide_rows.size(); ++i) {
    INFO("guide row " << i + 1 << ": " << guide_rows[i].construct);
    CHECK(help_rows[i].construct == guide_rows[i].construct);
    CHECK(help_rows[i].example == guide_rows[i].example);
  }
  CHECK(help_sections == guide_sections);
}
