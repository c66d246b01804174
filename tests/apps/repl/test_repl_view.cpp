// The text map and candidate descriptions, on hand-made world and candidate objects.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipper/repl/repl.hpp"

using flipper::kernel::Json;
using flipper::repl::describe_candidate;
using flipper::repl::render_map;

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

}  // namespace

TEST_CASE("the map puts max y on top, walls, robot and items", "[repl][view]") {
  Json world = Json::parse(R"({
    "walls":[[0,0],[1,0],[2,0],[3,0]],
    "items":[{"id":0,"x":2,"y":2,"color":"red","shape":"circle"},
             {"id":1,"x":1,"y":1,"color":"blue","shape":"square"},
             {"id":2,"x":1,"y":1,"color":"green","shape":"triangle"}],
    "robot":{"x":3,"y":2,"holding":[{"id":3,"color":"yellow","shape":"square"}]},
    "rooms":{"room1":[[1,1],[2,1]]},
    "bounds":{"min":[0,0],"max":[3,2]}})");
  auto l = lines(render_map(world));
  REQUIRE(l.size() >= 4);
  CHECK(l[0] == " 2 . . rcR ");
  CHECK(l[1] == " 1 . 2*. . ");
  CHECK(l[2] == " 0 ########");
  CHECK(l[3] == "   0 1 2 3   (x)");
  const std::string all = render_map(world);
  CHECK_THAT(all, Catch::Contains("rc red circle"));
  CHECK_THAT(all, Catch::Contains("[1,1]: blue square, green triangle"));
  CHECK_THAT(all, Catch::Contains("Robot at [3,2], holding: yellow square"));
  CHECK_THAT(all, Catch::Contains("room1 (x 1..2, y 1..1)"));
}

TEST_CASE("without bounds the map spans everything, with negative coordinates", "[repl][view]") {
  Json world = Json::parse(R"({"walls":[[-1,-1],[-1,0]],"items":[],
    "robot":{"x":0,"y":0,"holding":[]},"rooms":{}})");
  auto l = lines(render_map(world));
  REQUIRE(l.size() >= 3);
  CHECK(l[0] == " 0 ##R ");
  CHECK(l[1] == "-1 ##. ");
  CHECK(l[2] == "     0   (x)");  // -1 and 0 would run together: only multiples of 5
  CHECK_THAT(render_map(world), Catch::Contains("holding: nothing"));
}

TEST_CASE("a candidate is described by steps, picks, drops and warnings", "[repl][view]") {
  Json c = Json::parse(R"({"rank":0,"score":5,"prob":0.75,"formula":"{visit room1}","induced":true,
    "rules":["r7"],"authors":["ana"],"realizable":false,
    "trace":[{"act":"move","to":[3,4]},{"act":"move","to":[4,4]},
             {"act":"pick","at":[4,4],"item":{"id":1,"color":"red","shape":"circle"}},
             {"act":"drop","at":[4,4],"item":{"id":1,"color":"red","shape":"circle"}}],
    "world":{},"warnings":["Could not complete the action: {pick item}"]})");
  const std::string d = describe_candidate(c, 2);
  CHECK_THAT(d, Catch::StartsWith("  [2] {visit room1}   (p=0.75)"));
  CHECK_THAT(d, Catch::Contains(
                    "2 steps to [4,4]; picks: red circle at [4,4]; drops: red circle at [4,4]"));
  CHECK_THAT(d, Catch::Contains("NOT fully realizable"));
  CHECK_THAT(d, Catch::Contains("r7"));
  CHECK_THAT(d, Catch::Contains("ana"));
  CHECK_THAT(d, Catch::Contains("warning: Could not complete the action: {pick item}"));
  c["error"] = Json{{"code", "budget_exceeded"}, {"message", "action budget of 10 exceeded"}};
  CHECK_THAT(describe_candidate(c, 1), Catch::Contains("cannot be chosen"));
}

TEST_CASE("a trace is drawn as path, end, picks and drops, and the x axis labels every 5th column",
          "[repl][view]") {
  Json world =
      Json::parse(R"({"walls":[],"items":[{"id":0,"x":3,"y":0,"color":"red","shape":"circle"}],
    "robot":{"x":0,"y":0,"holding":[]},"rooms":{},"bounds":{"min":[-1,0],"max":[12,1]}})");
  Json trace = Json::parse(R"([{"act":"move","to":[1,0]},{"act":"move","to":[2,0]},
    {"act":"move","to":[2,1]},{"act":"pick","at":[2,1],"item":{"id":9,"color":"red","shape":"square"}},
    {"act":"move","to":[3,1]}])");
  flipper::repl::MapOptions o;
  o.trace = &trace;
  auto l = lines(render_map(world, o));
  REQUIRE(l.size() >= 3);
  CHECK(l[0] == " 1 . . . P E . . . . . . . . . ");
  CHECK(l[1] == " 0 . R o o rc. . . . . . . . . ");
  CHECK(l[2] == "     0         5         10      (x)");
  CHECK_THAT(render_map(world, o), Catch::Contains("o path, E end"));
}

TEST_CASE("3-D: the floor is labelled, z kept, other floors' items listed", "[repl][view]") {
  Json world = Json::parse(R"({"walls":[[1,0,0]],"items":[
      {"id":0,"x":0,"y":0,"z":1,"color":"red","shape":"circle"}],
    "robot":{"x":0,"y":0,"z":0,"holding":[]},"rooms":{"up":[[1,0,1]]},
    "bounds":{"min":[0,0,0],"max":[1,0,1]}})");
  const std::string ground = render_map(world);
  CHECK_THAT(ground,
             Catch::StartsWith("Floor z=0 (floors 0..1; :floor N shows another)\n 0 R ##\n"));
  CHECK_THAT(ground, Catch::Contains("floor z=1: red circle at [0,0,1]"));
  CHECK_THAT(ground, Catch::Contains("Robot at [0,0,0]"));
  CHECK_THAT(ground, Catch::Contains("up (x 1..1, y 0..0, z 1)"));
  flipper::repl::MapOptions o;
  o.floor = 1;
  CHECK_THAT(render_map(world, o),
             Catch::StartsWith("Floor z=1 (floors 0..1; :floor N shows another)\n 0 rc. \n"));
}

TEST_CASE("repeated warnings collapse and unknown words get a hint", "[repl][view]") {
  using flipper::repl::collapse_warnings;
  using flipper::repl::unknown_words;
  const auto w = collapse_warnings(Json::parse(R"(["a","b","a","a"])"));
  REQUIRE(w.size() == 2);
  CHECK(w[0] == "3 \u00d7 a");
  CHECK(w[1] == "b");
  const auto u = unknown_words({"vist", "room1", "3", "zzzzzz", "vist"}, {"visit", "room1"});
  REQUIRE(u.size() == 2);
  CHECK(u[0] == "'vist' (did you mean 'visit'?)");
  CHECK(u[1] == "'zzzzzz'");
}
