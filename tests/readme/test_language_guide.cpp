// docs/language.md: every example of its construct table, run on the study map with
// `flipper run --json`, ends where the guide says, moving, picking, dropping and warning as it
// says. The table is read through the repl's embedded copy (guide_examples), so this also checks
// that `:examples` shows the guide as it is.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_test_support.hpp"
#include "flipper/repl/repl.hpp"

using nlohmann::json;

namespace {

// `flipper run --json` of `program`: its stdout (its stderr goes to the test's own, which ctest
// shows beside a failure). It must exit normally with 0 or 1 (a failure's JSON); a sanitizer's
// report also exits 1, and its stderr then says so.
std::string flipper_run_json(const std::string& program) {
  const flipper::clitest::Run r =
      flipper::clitest::run_flipper("run --json --set lexicon.path=:memory: '" + program + "'",
                                    false);  // run_shell: killed by no signal
  INFO("flipper run --json '" << program << "': exit status " << r.status);
  REQUIRE(r.status <= 1);
  return r.out;
}

std::string plural(std::size_t n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// "ends at [x,y], N moves[; picks a, b][; drops c][; K warnings]" -- the guide's result format.
std::string summary(const json& a) {
  std::size_t moves = 0;
  std::string picks, drops;
  for (const auto& s : a["trace"]) {
    const std::string act = s["act"];
    if (act == "move") {
      ++moves;
      continue;
    }
    std::string& list = act == "pick" ? picks : drops;
    list += (list.empty() ? "" : ", ") + s["item"]["color"].get<std::string>() + " " +
            s["item"]["shape"].get<std::string>();
  }
  const json& r = a["world"]["robot"];
  std::string out = "ends at [" + std::to_string(r["x"].get<int>()) + "," +
                    std::to_string(r["y"].get<int>()) + "], " + plural(moves, "move");
  if (!picks.empty()) out += "; picks " + picks;
  if (!drops.empty()) out += "; drops " + drops;
  if (!a["warnings"].empty()) out += "; " + plural(a["warnings"].size(), "warning");
  return out;
}

}  // namespace

TEST_CASE("every example of the language guide does what the guide says", "[readme][guide]") {
  const auto examples = flipper::repl::guide_examples();
  // The guide's table, counted independently of the parser under test.
  std::ifstream md(std::string(FLIPPER_SOURCE_DIR) + "/docs/language.md");
  std::stringstream text;
  text << md.rdbuf();
  std::size_t rows = 0;
  for (std::string line; std::getline(text, line);)
    rows += line.rfind("| ", 0) == 0 && line.find(" | `") != std::string::npos;
  REQUIRE(rows >= 30);
  REQUIRE(examples.size() == rows);
  for (const auto& e : examples) {
    INFO("docs/language.md example: " << e.example);
    const std::string out = flipper_run_json(e.example);
    INFO("flipper run --json: " << out);
    const json a = json::parse(out);
    REQUIRE(a["ok"] == true);
    CHECK(summary(a) == e.result);
  }
  CHECK_THAT(flipper::repl::examples_text(), Catch::Contains("  visit room1\n"));
}
