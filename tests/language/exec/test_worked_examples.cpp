// core-language §10: the worked examples on the 2018 study map, traces checked exactly.
#include <catch2/catch.hpp>

#include "study_fixture.hpp"

using namespace flipper;
using flipper::testsupport::items_at;
using flipper::testsupport::Study;
using flipper::testsupport::trace_text;
using S = std::vector<std::string>;

TEST_CASE("10.1 visit world containing item is red", "[exec][examples]") {
  Study st;
  auto o = st.run("{visit {world containing item {is red}}}", st.state());
  REQUIRE_FALSE(o.error);
  CHECK(trace_text(o.trace) == "m(3,4) m(4,4) m(5,4) m(6,4) m(7,4)");
  CHECK(o.warnings.empty());
  CHECK(o.realizable);
  CHECK(o.world.robot == sdk::Cell{7, 4, 0});
}

TEST_CASE("10.2 visit and pick a red item", "[exec][examples]") {
  Study st;
  auto o = st.run("{{visit {world containing item {is red}}};{pick item {is red}}}", st.state());
  CHECK(trace_text(o.trace) == "m(3,4) m(4,4) m(5,4) m(6,4) m(7,4) p(7,4)red circle");
  REQUIRE(o.world.held.size() == 1);
  CHECK(o.world.held[0].color == "red");
  CHECK(items_at(o.world, 7, 4) == S{"blue circle", "green square", "green circle"});
  CHECK(o.realizable);
}

TEST_CASE("10.3 a failed move leaves the robot in place", "[exec][examples]") {
  Study st;
  auto o = st.run("{{move up};{move up}}", st.state());
  CHECK(trace_text(o.trace) == "m(2,5)");
  CHECK(o.world.robot == sdk::Cell{2, 5, 0});
  CHECK(o.warnings == S{"Could not complete the action: {move up} ([2,6] is a wall)"});
  CHECK_FALSE(o.realizable);
  CHECK_FALSE(o.error);
}

TEST_CASE("10.4 strict rolls back", "[exec][examples]") {
  Study st;
  auto o = st.run("{strict {{move up};{move up}}}", st.state());
  CHECK(o.trace.empty());
  CHECK(o.world.robot == sdk::Cell{2, 4, 0});
  CHECK(o.warnings == S{"Could not complete the action: {move up} ([2,6] is a wall)",
                        "Could not complete the action: {strict {{move up};{move up}}}"});
  CHECK_FALSE(o.realizable);
}

TEST_CASE("10.5 foreach area in a list of rooms", "[exec][examples]") {
  Study st;
  const char* prog = "{foreach area in {[room1, room2]} {{visit area};{drop item }}}";
  auto o = st.run(prog, st.state());
  // room2 is 4 steps away (first reached at (1,1)), room1 is reached through (8,0).
  CHECK(trace_text(o.trace).rfind("m(1,4) m(1,3) m(1,2) m(1,1) ", 0) == 0);
  CHECK(o.trace.size() == 13);
  CHECK(o.world.robot == sdk::Cell{9, 0, 0});
  CHECK(o.warnings == S{"Could not complete the action: {drop item } (no item held)",
                        "Could not complete the action: {drop item } (no item held)"});
  // Holding two items, one is dropped in each room.
  auto h = st.run(prog, st.state(2, 4, {{"red", "square"}, {"blue", "circle"}}));
  CHECK(h.warnings.empty());
  CHECK(items_at(h.world, 1, 1) == S{"red square"});
  CHECK(items_at(h.world, 9, 0) == S{"blue circle"});
  CHECK(h.world.held.empty());
}

TEST_CASE("10.6 visit while avoiding", "[exec][examples]") {
  Study st;
  auto o = st.run("{visit [9,8] while avoiding room3}", st.state());
  CHECK(o.trace.empty());
  CHECK(o.world.robot == sdk::Cell{2, 4, 0});
  CHECK(o.warnings ==
        S{"Could not complete the action: {visit [9,8] while avoiding room3} ([9,8] is unreachable "
          "while avoiding room3)"});
  auto ok = st.run("{visit [9,8] while avoiding room3}", st.state(7, 7));
  CHECK(ok.warnings.empty());
  CHECK(ok.world.robot == sdk::Cell{9, 8, 0});
  CHECK(trace_text(ok.trace) == "m(8,7) m(9,7) m(9,8)");
  // Without the avoid set the same visit succeeds from (2,4) through the opening at (5,6).
  auto free = st.run("{visit [9,8]}", st.state());
  CHECK(free.warnings.empty());
  CHECK(free.world.robot == sdk::Cell{9, 8, 0});
  CHECK(free.trace.size() == 11);
}

TEST_CASE("10.7 if not robot has item is red pick item", "[exec][examples]") {
  Study st;
  const char* prog = "{if {not {robot has item {is red}}} {pick item }}";
  auto none = st.run(prog, st.state());
  CHECK(none.warnings == S{"Could not complete the action: {pick item } (no item here)"});
  auto at = st.run(prog, st.state(7, 4));
  CHECK(trace_text(at.trace) == "p(7,4)red circle");
  auto holding = st.run(prog, st.state(7, 4, {{"red", "square"}}));
  CHECK(holding.trace.empty());
  CHECK(holding.warnings.empty());
  CHECK(holding.realizable);
}
