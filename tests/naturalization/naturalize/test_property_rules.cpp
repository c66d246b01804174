// `$Property` through the session protocol (docs/naturalization.md §4 example): `gather red` and
// `red to room1` are defined with a colour, and a shape then works in their place — the rule holes
// are Property holes — also after a restart (the stored templates read back).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <set>
#include <tuple>

#include "naturalize_fixture.hpp"
#include "session_fixture.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

// Two triangles, a red circle and a green square outside room1 (x >= 6); the robot at the origin.
const Json kWorld = Json::parse(R"({
  "walls": [],
  "items": [{"x": 2, "y": 1, "color": "red", "shape": "triangle"},
            {"x": 4, "y": 3, "color": "blue", "shape": "triangle"},
            {"x": 1, "y": 3, "color": "red", "shape": "circle"},
            {"x": 3, "y": 0, "color": "green", "shape": "square"}],
  "robot": {"x": 0, "y": 0, "holding": []},
  "rooms": {"room1": [[6, 0], [6, 1], [7, 0], [7, 1]], "room2": [[6, 3], [7, 3]]},
  "bounds": {"min": [0, 0], "max": [7, 3]}
})");

bool in_room1(const Json& item) {
  return item["x"].get<int>() >= 6 && item["y"].get<int>() <= 1;
}

/// (colour, shape, x, y) of every item lying in a world answer.
std::set<std::tuple<std::string, std::string, int, int>> items(const Json& world) {
  std::set<std::tuple<std::string, std::string, int, int>> out;
  for (const auto& i : world["items"])
    out.insert({i["color"], i["shape"], i["x"].get<int>(), i["y"].get<int>()});
  return out;
}

Json query(kernel::Session& s, const std::string& text) {
  return s.handle({{"op", "query"}, {"text", text}});
}

bool has_rule(const Json& define_answer, const std::string& how, const Json& rhs) {
  for (const auto& r : define_answer["rules"])
    if (r["how"] == how && r["rhs"] == rhs) return true;
  return false;
}

const char* const kTriangleToRoom1 =
    "foreach point in world containing item is triangle {visit point; pick every item is "
    "triangle}; visit room1; drop every item is triangle";

}  // namespace

TEST_CASE("a colour in a definition is a property: triangle to room1 after red to room1",
          "[naturalize][property]") {
  const std::string store = testsupport::scratch_path("property") + ".sqlite";
  auto s = open(store);
  REQUIRE(s->handle({{"op", "world"}, {"world", kWorld}})["ok"] == true);
  user(*s, "ana");
  CHECK(status(*s, "triangle to room1") == "unparsable");
  // `has color` still takes colours only; `is` takes both.
  CHECK(status(*s, "visit world containing item has color triangle") == "unparsable");
  CHECK(status(*s, "visit world containing item has shape triangle") == "core");

  const Json gather = define(
      *s, "gather red",
      {"foreach point in world containing item is red {visit point; pick every item is red}"});
  REQUIRE(gather["ok"] == true);
  CHECK(has_rule(gather, "best", Json::array({"gather", "$Property"})));
  const Json to =
      define(*s, "red to room1", {"gather red", "visit room1", "drop every item is red"});
  REQUIRE(to["ok"] == true);
  CHECK(has_rule(to, "best", Json::array({"$Property", "to", "$Area"})));

  const Json core = query(*s, kTriangleToRoom1);
  REQUIRE(core["status"] == "core");
  const Json q = query(*s, "triangle to room1");
  REQUIRE(q["status"] == "induced");
  REQUIRE_FALSE(q["candidates"].empty());
  const Json& top = q["candidates"][0];
  CHECK(top["formula"] == core["candidates"][0]["formula"]);
  CHECK(top["induced"] == true);
  CHECK(top["realizable"] == true);

  // Executed: both triangles picked and dropped in room1, nothing else touched.
  int picks = 0;
  int drops = 0;
  for (const auto& step : top["trace"]) {
    if (step["act"] == "pick") {
      ++picks;
      CHECK(step["item"]["shape"] == "triangle");
    }
    if (step["act"] == "drop") {
      ++drops;
      CHECK(step["item"]["shape"] == "triangle");
      CHECK(step["at"][0].get<int>() >= 6);
      CHECK(step["at"][1].get<int>() <= 1);
    }
  }
  CHECK(picks == 2);
  CHECK(drops == 2);
  const Json accepted = s->handle({{"op", "accept"}, {"rank", 0}});
  REQUIRE(accepted["ok"] == true);
  const Json& after = accepted["world"];
  CHECK(after["robot"]["holding"].empty());
  int triangles = 0;
  for (const auto& i : after["items"]) {
    if (i["shape"] == "triangle") {
      ++triangles;
      CHECK(in_room1(i));
    } else {
      CHECK_FALSE(in_room1(i));
    }
  }
  CHECK(triangles == 2);
  CHECK(items(after).count({"red", "circle", 1, 3}) == 1);
  CHECK(items(after).count({"green", "square", 3, 0}) == 1);

  // The colour reading is unchanged, and both compose in one command.
  CHECK(status(*s, "red to room1") == "induced");
  CHECK(status(*s, "circle to room2; green to room1") == "induced");

  // After a restart the stored templates (with Property holes) read back and still take shapes.
  s.reset();
  auto again = open(store);
  REQUIRE(again->handle({{"op", "world"}, {"world", kWorld}})["ok"] == true);
  user(*again, "ana");
  const Json q2 = query(*again, "triangle to room1");
  REQUIRE(q2["status"] == "induced");
  CHECK(q2["candidates"][0]["formula"] == core["candidates"][0]["formula"]);
  CHECK(status(*again, "gather square") == "induced");
}
