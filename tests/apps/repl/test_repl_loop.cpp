// The repl loop on a real session, reading a script (no terminal).
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "flipper/repl/repl.hpp"
#include "session_fixture.hpp"

namespace {

std::string run_script(flipper::kernel::Session& s, const std::string& script) {
  std::istringstream in(script);
  std::ostringstream out;
  auto reader = flipper::repl::make_line_reader(in, false);
  CHECK(flipper::repl::run(s, *reader, out) == 0);
  return out.str();
}

}  // namespace

TEST_CASE("repl: query, choose, the robot moves", "[repl][loop]") {
  auto s = flipper::testsupport::bare_session();
  const std::string out = run_script(*s, "move left\n1\n:quit\nmove up\n");
  // The start map has the robot at [2,4]; after choosing 1 it is at [1,4].
  CHECK_THAT(out, Catch::Contains(" 4 ##. . R "));
  CHECK_THAT(out, Catch::Contains("[1] {move left}"));
  CHECK_THAT(out, Catch::Contains("Done: 1 step."));
  CHECK_THAT(out, Catch::Contains(" 4 ##. R . "));
  CHECK(s->world().robot.x == 1);
  // Nothing after :quit ran.
  CHECK(s->world().robot.y == 4);
}

TEST_CASE("repl: reject, unparsable, commands and errors", "[repl][loop]") {
  auto s = flipper::testsupport::bare_session();
  const std::string out =
      run_script(*s,
                 "move left\nr\n7\nzorp blah\n:user ana\n:help\n:examples\n:rules\n"
                 ":define zorp blah\nmove left\n\n:bogus\n:world /no/such.json\n");
  CHECK_THAT(out, Catch::Contains("Rejected."));
  CHECK(s->world().robot.x == 2);  // nothing was accepted
  CHECK_THAT(out, Catch::Contains("I did not understand that"));
  CHECK_THAT(out, Catch::Contains("You are ana."));
  CHECK(s->user() == "ana");
  CHECK_THAT(out, Catch::Contains(":define HEAD"));
  // :examples is the language guide's table (docs/language.md), embedded in the binary.
  CHECK_THAT(out,
             Catch::Contains("  strict {move left; move left; move left}\n"
                             "      strict: all or nothing: ends at [2,4], 0 moves; 2 warnings"));
  CHECK_THAT(out, Catch::Contains("Defining \"zorp blah\""));
  CHECK_THAT(out, Catch::Contains("Unknown command :bogus"));
  CHECK_THAT(out, Catch::Contains("error (bad_world)"));
}

TEST_CASE("repl: a sentence it does not understand gets its repair", "[repl][loop][repair]") {
  auto s = flipper::testsupport::bare_session();
  const std::string out = run_script(*s, "move up xyzzy\nmove up move left\n");
  CHECK_THAT(out, Catch::Contains("I did not understand that. Unknown word: 'xyzzy'."));
  CHECK_THAT(out, Catch::Contains("Understood: \"move up\" = {move up}.\n"
                                  "Not understood: 'xyzzy' (unknown).\n"
                                  "Nearest sentences I understand:\n"
                                  "  1. move up   (drop 'xyzzy')\n"
                                  "Teach it: `:define`, then the steps: \"move up\".\n"));
  CHECK_THAT(out, Catch::Contains("  1. move up ; move left   (insert ';' after 'move up')\n"
                                  "  2. move up   (keep only 'move up')\n"));
  CHECK_THAT(out,
             Catch::Contains("Teach it: `:define`, then the steps: \"move up\" \"move left\"."));
}

TEST_CASE("repl: a reading that cannot be done here says why and what can",
          "[repl][loop][repair]") {
  auto s = flipper::testsupport::bare_session();
  const std::string out = run_script(*s, "pick item is red\n");
  CHECK_THAT(out, Catch::Contains(
                      "      Cannot be done here: {pick item {is red}} fails at [2,4]: no red item "
                      "at [2,4], where the robot is; one lies in room2, room3, room5. Nearest "
                      "that works: {{visit {world containing item {is red}}};{pick item {is "
                      "red}}} (visit 'world containing item {is red}' first).\n"));
}

TEST_CASE("repl: :floor in a 2-D world says the world is flat", "[repl][loop]") {
  auto s = flipper::testsupport::bare_session();
  const std::string out = run_script(*s, ":floor 1\n");
  CHECK_THAT(out, Catch::Contains("This world is flat (2-D): it has no floors, and the map shows "
                                  "all of it. :floor is for 3-D worlds."));
  CHECK_THAT(out, !Catch::Contains("Floor z=1"));
}

TEST_CASE("repl: define an unparsable utterance, then use it", "[repl][loop]") {
  // open_session installs every module's ops (naturalization: define, rules).
  auto s = flipper::wiring::open_session(flipper::testsupport::test_runtime());
  const std::string out =
      run_script(*s, "zig zag\n:define\nmove up\nmove right\n\nzig zag\n1\n:rules\n");
  CHECK_THAT(out, Catch::Contains("I did not understand that"));
  CHECK_THAT(out, Catch::Contains("Defining \"zig zag\""));
  CHECK_THAT(out, Catch::Contains("Learned 1 rule"));
  CHECK_THAT(out, Catch::Contains("[1] {{move up};{move right}}"));
  CHECK_THAT(out, Catch::Contains("uses definitions:"));
  CHECK_THAT(out, Catch::Contains("zig zag  =>  {{move up};{move right}}  (by anonymous"));
  CHECK(s->world().robot.x == 3);
  CHECK(s->world().robot.y == 5);
}

TEST_CASE("repl: :preview shows the rules' new sentences, then stores with one dropped",
          "[repl][loop]") {
  // docs/naturalization.md §5 "Preview": the examples are hand-derived (colours black blue gray
  // green, the head's own skipped; nothing to pick where the robot stands).
  auto s = flipper::wiring::open_session(flipper::testsupport::test_runtime());
  const std::string out =
      run_script(*s, ":preview zap blue\npick item is blue\n\nnew2 new3\n:rules\n");
  CHECK_THAT(out, Catch::Contains("new1: $Action -> zap $Color  =>  {pick item {is $1}}\n"
                                  "    \"zap black\" -> {pick item {is black}}: 0 moves, 0 picks, "
                                  "0 drops, not realizable here\n"));
  CHECK_THAT(out, Catch::Contains("new3: $Action -> zap blue  =>  {pick item {is blue}}\n"
                                  "    (reads only \"zap blue\")\n"));
  CHECK_THAT(out, Catch::Contains("Perturbed check: not run"));
  CHECK_THAT(out, Catch::Contains("Learned 1 rule"));
  CHECK_THAT(out, Catch::Contains("zap $Color  =>  {pick item {is $1}}  (by anonymous"));
  CHECK_THAT(out, !Catch::Contains("zap $Property  =>  {pick item {is $1}}  (by"));
}

TEST_CASE("repl: :save draws the plan just chosen", "[repl][loop]") {
  auto s = flipper::testsupport::bare_session();
  const std::string file = std::string(FLIPPER_BINARY_DIR) + "/tests/tmp/repl-save.svg";
  std::remove(file.c_str());
  const std::string out = run_script(*s, "visit [5,4]\n1\n:save " + file + "\n");
  CHECK_THAT(out, Catch::Contains("Saved the plan and its world to " + file));
  std::ifstream in(file);
  std::stringstream svg;
  svg << in.rdbuf();
  // From [2,4] three cells right: four points, 28 px apart.
  CHECK_THAT(svg.str(),
             Catch::Contains("points=\"134.0,198.0 162.0,198.0 190.0,198.0 218.0,198.0 \""));
  CHECK_THAT(svg.str(), Catch::Contains(">{visit [5,4]}</text>"));
}
