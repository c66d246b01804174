// Pictures: `flipper run --svg FILE` and the repl's `:save FILE` draw the world and the plan
// (apps/svg).
#include <nlohmann/json.hpp>
#include <regex>

#include "cli_test_support.hpp"

using namespace flipper::clitest;

namespace {
int count(const std::string& text, const std::string& word) {
  int n = 0;
  for (auto pos = text.find(word); pos != std::string::npos; pos = text.find(word, pos + 1)) ++n;
  return n;
}
}  // namespace

TEST_CASE("run --svg draws walls, items, the robot and the path", "[cli][svg]") {
  const std::string file = scratch("plan.svg");
  const Run r = run_flipper("run --set lexicon.path=:memory: --svg " + file +
                            " 'visit [7,4]; pick item is red'");
  INFO(r.out);
  REQUIRE(r.status == 0);
  const std::string svg = read_file(file);
  CHECK(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0) == 0);
  CHECK(svg.find("</svg>") != std::string::npos);
  // The title is the program in canonical text.
  CHECK(contains(svg, ">{{visit [7,4]};{pick item {is red}}}</text>"));
  // One dark square per wall of the study map's file (inside the bounds), plus the legend's.
  std::ifstream world_file(std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds/study2018.json");
  const auto world = nlohmann::json::parse(world_file);
  CHECK(count(svg, "fill=\"#555\" stroke=") == static_cast<int>(world["walls"].size()) + 1);
  // The path: the robot's cell [2,4] and the five cells right to [7,4] (28 px cells, x from -1
  // at 36 px, y from 9 at 44 px: cell (x,y) centre = (36+28(x+1)+14, 44+28(9-y)+14)).
  CHECK(contains(svg,
                 "points=\"134.0,198.0 162.0,198.0 190.0,198.0 218.0,198.0 246.0,198.0 "
                 "274.0,198.0 \""));
  CHECK(count(svg, ">P</text>") == 1);
  CHECK(contains(svg, "5 moves, 1 picks, 0 drops"));
}
