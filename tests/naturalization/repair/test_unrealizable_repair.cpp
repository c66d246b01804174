// Repairs of unrealizable candidates (docs/protocol.md § "Repairs", docs/naturalization.md § 7)
// through the protocol on a hand-made world. Expected values are worked out by hand:
//
//   y=2   .  r  .  #  .  .  .       room1 = [0,2] [1,2]   (r: red square at [1,2])
//   y=1   .  .  .  #  .  .  .       room3 = [2,0] [2,1]   (b: blue circle at [2,0])
//   y=0   R  .  b  #  .  .  .       room5 = [5,1] [6,1]   (behind the wall x = 3)
//        x=0 1  2  3  4  5  6       R: the robot at [0,0], on a green triangle
//
// Rooms nearest to room5 by bounding-box gap: room3 (3), room1 (4 + 1 = 5); to room3: room1
// (1 + 1 = 2), room5 (3). The world's item colours: blue, green, red; shapes: circle, square,
// triangle.
#include <catch2/catch.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/naturalization/unrealizable.hpp"
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;

namespace {

Json world_with(const Json& extra_items = Json::array()) {
  Json w = Json::parse(R"({
    "walls": [[3,0],[3,1],[3,2]],
    "items": [{"x":2,"y":0,"color":"blue","shape":"circle"},
              {"x":1,"y":2,"color":"red","shape":"square"},
              {"x":0,"y":0,"color":"green","shape":"triangle"}],
    "robot": {"x":0,"y":0,"holding":[]},
    "rooms": {"room1": [[0,2],[1,2]], "room3": [[2,0],[2,1]], "room5": [[5,1],[6,1]]},
    "bounds": {"min":[0,0],"max":[6,2]}})");
  for (const auto& i : extra_items) w["items"].push_back(i);
  return w;
}

std::unique_ptr<flipper::kernel::Session> session_on(const Json& world) {
  auto s = std::make_unique<flipper::kernel::Session>(
      flipper::testsupport::test_runtime(),
      flipper::kernel::Session::Extensions{
          std::make_shared<flipper::naturalization::RepairExtension>()});
  const Json w = ask(*s, Json{{"op", "world"}, {"world", world}}.dump());
  REQUIRE(w["ok"] == true);
  return s;
}

Json query(flipper::kernel::Session& s, const std::string& text, bool repair = true) {
  Json req{{"op", "query"}, {"text", text}, {"k", 1}};
  if (repair) req["repair"] = true;
  Json a = ask(s, req.dump());
  REQUIRE(a["ok"] == true);
  return a;
}

// The explanation of the best candidate, which must be unrealizable.
Json explained(flipper::kernel::Session& s, const std::string& text) {
  const Json a = query(s, text);
  REQUIRE(a["candidates"].size() == 1);
  CHECK(a["candidates"][0]["realizable"] == false);
  REQUIRE(a.contains("repair"));
  REQUIRE(a["repair"]["unrealizable"].size() == 1);
  Json u = a["repair"]["unrealizable"][0];
  CHECK(u["rank"] == 0);
  return u;
}

}  // namespace

TEST_CASE("a colour missing in a room: the colour that lies there", "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "visit room3 containing item is red");
  CHECK(u["step"] == "{visit {room3 containing item {is red}}}");
  CHECK(u["at"] == Json::parse("[0,0]"));
  CHECK(u["why"] == "no red item in room3");
  // Distance 1, item words first: 'red' -> 'blue' (alphabetical), and a blue item lies in room3.
  CHECK(u["variant"] == Json::parse(R"({"formula":"{visit {room3 containing item {is blue}}}",
                                        "edit":"replace 'red' by 'blue'","edits":1})"));
  CHECK(u["tried"] == 1);
  CHECK_FALSE(u.contains("limited"));
}

TEST_CASE("an unreachable room: the nearest reachable room", "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "visit room5");
  CHECK(u["step"] == "{visit room5}");
  CHECK(u["why"] == "room5 is unreachable from the robot's position [0,0]");
  CHECK(u["variant"] == Json::parse(R"({"formula":"{visit room3}",
                                        "edit":"replace 'room5' by 'room3'","edits":1})"));
  CHECK(u["tried"] == 1);
}

TEST_CASE("an empty intersection: no item is both, the nearest variant drops the condition",
          "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "pick item is red and is circle");
  CHECK(u["step"] == "{pick item {{is red} and {is circle}}}");
  CHECK(u["why"] == "no item is both red and a circle");
  // Tried in order: visit a red circle first (none lies anywhere); red -> blue, green; circle ->
  // square, triangle (distance 1); drop 'is red',
  // drop 'is circle' (3); drop the whole condition (5): only a plain item lies at [0,0].
  // (A plain item renders "{pick item }", as a query of "pick item" answers.)
  CHECK(u["variant"] == Json::parse(R"({"formula":"{pick item }",
                                        "edit":"drop '{is red} and {is circle}'","edits":5})"));
  CHECK(u["tried"] == 8);
}

TEST_CASE("a pick where the robot is not: where such items lie", "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "pick item is red");
  CHECK(u["why"] == "no red item at [0,0], where the robot is; one lies in room1");
  // The nearest variant goes to the red square first (one statement inserted).
  CHECK(u["variant"] ==
        Json::parse(R"({"formula":"{{visit {world containing item {is red}}};{pick item {is red}}}",
                        "edit":"visit 'world containing item {is red}' first","edits":1})"));
  CHECK(u["tried"] == 1);
  // Behind the wall the red square is out of reach: 'red' -> 'blue' fails (no blue item at
  // [0,0]); -> 'green' is the green triangle there.
  Json walled = world_with();
  walled["items"][1]["x"] = 6;
  auto behind = session_on(walled);
  const Json b = explained(*behind, "pick item is red");
  CHECK(b["why"] == "no red item at [0,0], where the robot is; one lies outside every room");
  CHECK(b["variant"]["formula"] == "{pick item {is green}}");
  CHECK(b["tried"] == 3);
}

TEST_CASE("the failing step of a sequence, and a variant that fails too: none found",
          "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "move right ; visit room5 ; visit room5");
  // The move succeeds: the step is the first visit, from the cell the move reached.
  CHECK(u["step"] == "{visit room5}");
  CHECK(u["at"] == Json::parse("[1,0]"));
  CHECK(u["why"] == "room5 is unreachable from the robot's position [1,0]");
  // Each edit of the first visit leaves the second one failing: room3, then room1.
  CHECK(u["variant"].is_null());
  CHECK(u["tried"] == 2);
  CHECK_FALSE(u.contains("limited"));
}

TEST_CASE("variants are bounded by count: 8 are tried, a 9th is left out",
          "[session][repair][limits]") {
  using flipper::naturalization::kMaxVariantRuns;
  REQUIRE(kMaxVariantRuns == 8);
  // No edit of the pick makes the trailing visit of room5 possible. Eight edits as above, plus
  // one colour word per extra colour of the world (a yellow item behind the wall).
  const Json yellow{{"x", 6}, {"y", 2}, {"color", "yellow"}, {"shape", "circle"}};
  const std::string text = "pick item is red and is circle ; visit room5";
  auto at = session_on(world_with());
  const Json eight = explained(*at, text);
  CHECK(eight["step"] == "{pick item {{is red} and {is circle}}}");
  CHECK(eight["variant"].is_null());
  CHECK(eight["tried"] == 8);
  CHECK_FALSE(eight.contains("limited"));
  auto over = session_on(world_with(Json::array({yellow})));
  const Json nine = explained(*over, text);
  CHECK(nine["variant"].is_null());
  CHECK(nine["tried"] == 8);
  CHECK(nine["limited"] == "only the first 8 of 9 variants were tried");
}

TEST_CASE("an unknown room: the kernel's error is the reason, a room of the world the variant",
          "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "visit room9");
  CHECK(u["why"] == "unknown room 'room9' (this world defines room1, room3, room5)");
  CHECK(u["variant"]["formula"] == "{visit room1}");  // no such room: rooms by name
}

TEST_CASE("realizable answers and answers without repair are unchanged", "[session][repair]") {
  auto s = session_on(world_with());
  const auto masked = [&](const Json& req) {
    Json a = Json::parse(s->handle_line(req.dump()));
    a["ms"] = 0;
    return a.dump();
  };
  CHECK(masked({{"op", "query"}, {"text", "visit room3"}, {"repair", true}}) ==
        masked({{"op", "query"}, {"text", "visit room3"}}));
  const Json plain = query(*s, "visit room5", false);
  CHECK(plain["candidates"][0]["realizable"] == false);
  CHECK_FALSE(plain.contains("repair"));
}

TEST_CASE("a drop with nothing held: every edit fails too", "[session][repair]") {
  auto s = session_on(world_with());
  const Json u = explained(*s, "drop item is red");
  CHECK(u["why"] == "the robot holds nothing");
  // 'red' -> 'blue', 'green', then drop 'is red': the robot holds no item at all.
  CHECK(u["variant"].is_null());
  CHECK(u["tried"] == 3);
}

TEST_CASE("finding the step is bounded by count: 48 executions, not 49",
          "[session][repair][limits]") {
  using flipper::naturalization::kMaxExplainRuns;
  namespace sdk = flipper::sdk;
  REQUIRE(kMaxExplainRuns == 48);
  auto s = session_on(world_with());
  const auto run = [&](const sdk::Program& p, const sdk::WorldState& w) {
    return s->executor().run(p, w);
  };
  // `moves` moves that succeed (right, left, right, ...), then `visit room5`: the descent
  // executes each statement once, so the step is found with moves + 1 executions.
  const auto explain = [&](int moves) {
    std::vector<sdk::Program> steps;
    steps.reserve(static_cast<std::size_t>(moves) + 1);
    for (int i = 0; i < moves; ++i)
      steps.push_back(sdk::make(sdk::Kind::Move,
                                {sdk::make_word(sdk::Kind::Direction, i % 2 ? "left" : "right")}));
    steps.push_back(sdk::make(sdk::Kind::VisitArea, {sdk::make_word(sdk::Kind::Room, "room5")}));
    const sdk::Program p = sdk::make_seq(steps);
    const sdk::Outcome o = run(p, s->world());
    REQUIRE_FALSE(o.realizable);
    return flipper::naturalization::explain_unrealizable(p, s->world(), o, run);
  };
  const auto at = explain(47);
  CHECK(sdk::render(at.step) == "{visit room5}");
  CHECK(at.why == "room5 is unreachable from the robot's position [1,0]");
  CHECK(at.limited.empty());
  CHECK(at.runs == 48 + 1);  // and one variant, `visit room3`
  REQUIRE(at.variant);
  CHECK(at.variant->edit == "replace 'room5' by 'room3'");
  const auto over = explain(48);
  CHECK(over.step->kind == sdk::Kind::Seq);  // the descent stopped at the whole program
  CHECK(over.why == "Could not complete the action: {visit room5} (room5 is unreachable)");
  CHECK(over.limited == "the step and its reason took more than 48 executions");
  CHECK(over.runs == 48);
  CHECK_FALSE(over.variant);
}
