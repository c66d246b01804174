#include <catch2/catch.hpp>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"
#include "study_world.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

std::shared_ptr<sdk::World> grid() {
  static auto w = testsupport::load_plugin<sdk::World>("grid2d");
  return w;
}

// A small valid world the bad cases below each break in one place.
const char* const kBase = R"("walls": [[0,0],[1,0],[2,0],[0,1],[2,1],[0,2],[1,2],[2,2]])";

std::string with(const std::string& rest) {
  return std::string("{") + kBase + "," + rest + "}";
}

}  // namespace

TEST_CASE("grid2d loads the study map with its walls, items, rooms and robot", "[grid2d]") {
  const sdk::WorldState s = grid()->load(testsupport::study_world_json(), ".");
  const sdk::Geometry& g = *s.geometry;
  REQUIRE(g.dims() == 2);
  REQUIRE(g.min() == Cell{-1, -1, 0});
  REQUIRE(g.max() == Cell{12, 9, 0});
  REQUIRE(s.robot == Cell{2, 4, 0});
  REQUIRE(s.held.empty());
  REQUIRE(s.items.size() == 11);
  REQUIRE(s.items[4].at == Cell{7, 4, 0});
  REQUIRE(s.items[4].item.color == "red");
  REQUIRE(s.items[4].item.shape == "circle");
  for (std::size_t i = 0; i < s.items.size(); ++i)
    REQUIRE(s.items[i].item.id == static_cast<std::int64_t>(i));
  REQUIRE(s.next_item_id == 11);
  REQUIRE(!g.is_free({2, 6, 0}));
  REQUIRE(!g.is_free({8, 1, 0}));
  REQUIRE(g.is_free({5, 6, 0}));
  REQUIRE(g.is_free({9, 6, 0}));
  REQUIRE(g.free_cells().size() == 14 * 11 - 70);
  REQUIRE(s.rooms->size() == 5);
  REQUIRE(s.rooms->at("room3").size() == 32);
  REQUIRE(g.neighbour_offsets() == std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}});
  REQUIRE(g.direction("up") == Cell{0, 1, 0});
  REQUIRE(g.direction("down") == Cell{0, -1, 0});
  REQUIRE(g.direction("left") == Cell{-1, 0, 0});
  REQUIRE(g.direction("right") == Cell{1, 0, 0});
}

TEST_CASE("grid2d loads every corpus world", "[grid2d][corpus]") {
  const auto worlds = testsupport::corpus_worlds();
  REQUIRE(worlds.size() > 1000);
  for (const auto& text : worlds) {
    INFO(text.substr(0, 40));
    const sdk::WorldState s = grid()->load(text, ".");
    REQUIRE(s.geometry->is_free(s.robot));
  }
}

TEST_CASE("grid2d defaults the bounds to the smallest box around everything", "[grid2d]") {
  const sdk::WorldState s = grid()->load(
      R"({"walls": [[0, 0]], "items": [{"x": 5, "y": 1, "color": "red", "shape": "square"}],
          "robot": {"x": 1, "y": -2}, "rooms": {"r": [[2, 7]]}})",
      ".");
  REQUIRE(s.geometry->min() == Cell{0, -2, 0});
  REQUIRE(s.geometry->max() == Cell{5, 7, 0});
  REQUIRE(!s.geometry->is_free({0, 0, 0}));
  REQUIRE(s.geometry->is_free({0, 1, 0}));
}

TEST_CASE("grid2d keeps given ids and assigns the rest in order", "[grid2d]") {
  const sdk::WorldState s =
      grid()->load(with(R"("items": [{"x": 1, "y": 1, "color": "red", "shape": "square"},
                        {"x": 1, "y": 1, "color": "blue", "shape": "circle", "id": 0},
                        {"x": 1, "y": 1, "color": "blue", "shape": "square"}],
              "robot": {"x": 1, "y": 1, "holding": [{"color": "pink", "shape": "circle"},
                                                   {"color": "red", "shape": "circle", "id": 7}]})"),
                   ".");
  REQUIRE(s.items[0].item.id == 1);
  REQUIRE(s.items[1].item.id == 0);
  REQUIRE(s.items[2].item.id == 2);
  REQUIRE(s.held[0].id == 3);
  REQUIRE(s.held[1].id == 7);
  REQUIRE(s.next_item_id == 8);
}

TEST_CASE("grid2d saves the normalised world object", "[grid2d]") {
  const sdk::WorldState s = grid()->load(
      R"({"walls": [[2,2],[0,0],[2,2]], "robot": {"x": 1, "y": 1, "holding": [{"color": "red", "shape": "circle"}]},
          "items": [{"x": 2, "y": 1, "color": "blue", "shape": "square"}],
          "rooms": {"b": [[1,1],[0,1]], "a": [[2,1]]}, "world_id": "ignored"})",
      ".");
  REQUIRE(
      grid()->save(s) ==
      R"({"walls":[[0,0],[2,2]],"items":[{"id":0,"x":2,"y":1,"color":"blue","shape":"square"}],)"
      R"("robot":{"x":1,"y":1,"holding":[{"id":1,"color":"red","shape":"circle"}]},)"
      R"("rooms":{"a":[[2,1]],"b":[[0,1],[1,1]]},"bounds":{"min":[0,0],"max":[2,2]}})");
}

TEST_CASE("grid2d rejects malformed worlds naming the entry", "[grid2d]") {
  struct Case {
    std::string json;
    std::string names;
  };
  const std::vector<Case> cases = {
      {"{\"robot\": {\"x\": 1, ", "not valid JSON"},
      {"42", "world must be a JSON object"},
      {with(R"("walls": [], "robot": {"x": 1, "y": 1})"), "duplicate key \"walls\""},
      {with(R"("items": [{"x": 1, "y": 1, "color": "red", "shape": "square"},
                        {"x": 1, "y": 1, "color": "red", "shape": "square"},
                        {"x": 1, "y": 1, "color": "red", "shape": "square"},
                        {"x": "1", "y": 1, "color": "red", "shape": "square"}],
               "robot": {"x": 1, "y": 1})"),
       "items[3]: x must be an integer"},
      {with(
           R"("items": [{"x": 1, "y": 1.5, "color": "red", "shape": "square"}], "robot": {"x": 1, "y": 1})"),
       "items[0]: y must be an integer"},
      {with(R"("items": [{"y": 1, "color": "red", "shape": "square"}], "robot": {"x": 1, "y": 1})"),
       "items[0]: missing \"x\""},
      {with(R"("items": [{"x": 1, "y": 1, "color": "red"}], "robot": {"x": 1, "y": 1})"),
       "items[0]: missing \"shape\""},
      {with(
           R"("items": [{"x": 1, "y": 1, "color": "red", "shape": "square", "id": "a"}], "robot": {"x": 1, "y": 1})"),
       "items[0]: id must be an integer"},
      {with(R"("items": [{"x": 1, "y": 1, "color": "red", "shape": "square", "id": 3},
                        {"x": 1, "y": 1, "color": "red", "shape": "square", "id": 3}], "robot": {"x": 1, "y": 1})"),
       "items[1]: duplicate id 3"},
      {with(R"("items": {"x": 1}, "robot": {"x": 1, "y": 1})"), "items must be an array"},
      {with(R"("robot": {"x": 1, "y": 2})"), "robot (1,2) is on a wall"},
      {with(R"("robot": {"x": 1, "y": 1}, "bounds": {"min": [0, 0], "max": [2, 2]},
               "items": [{"x": 1, "y": 1, "color": "red", "shape": "square"},
                         {"x": 20, "y": 3, "color": "red", "shape": "square"}])"),
       "items[1] (id 1) at (20,3) is outside the bounds"},
      {with(
           R"("robot": {"x": 1, "y": 1}, "items": [{"x": 2, "y": 1, "color": "red", "shape": "square"}])"),
       "items[0] (id 0) at (2,1) is on a wall"},
      {with(R"("robot": {"x": 5, "y": 5}, "bounds": {"min": [0, 0], "max": [2, 2]})"),
       "robot (5,5) is outside the bounds"},
      {with(
           R"("robot": {"x": 1, "y": 1}, "rooms": {"room1": [[1, 1]], "room2": [[1, 1]], "room2": [[1, 1]]})"),
       "rooms: duplicate room name \"room2\""},
      {with(R"("robot": {"x": 1, "y": 1}, "rooms": {"room1": [[1, 1], [1]]})"),
       "rooms.room1[1]: a point must be an array of 2 integers"},
      {with(R"("robot": {"x": 1, "y": 1}, "rooms": {"room1": [[1, 1], [9, 9]]},
               "bounds": {"min": [0, 0], "max": [2, 2]})"),
       "rooms.room1[1] (9,9) is outside the bounds"},
      {with(R"("robot": {"x": 1, "y": 1}, "bounds": {"min": [0, 0], "max": [-1, 2]})"),
       "bounds: min (0,0) exceeds max (-1,2)"},
      {with(R"("robot": {"x": 1, "y": 1}, "bounds": {"min": [0, 0]})"), "bounds: needs both"},
      {R"({"walls": [[0, 0], [7, 7]], "robot": {"x": 1, "y": 1}, "bounds": {"min": [0, 0], "max": [2, 2]}})",
       "walls: point (7,7) is outside the bounds"},
      {R"({"walls": [[0, 0], "x"], "robot": {"x": 1, "y": 1}})", "walls[1]: a point must be"},
      {R"({"walls": {}, "robot": {"x": 1, "y": 1}})", "walls must be an array of points"},
      {with(R"("robot": {"x": 1, "y": 1, "holding": [{"color": "red", "shape": 4}]})"),
       "robot.holding[0]: shape must be a string"},
      {with(R"("robot": {"x": 1, "y": 1, "holding": {}})"), "robot.holding must be an array"},
      {with(R"("robot": {"x": 1, "y": 1}, "octomap": "map.bt")"), "octomap"},
      {with(
           R"("robot": {"x": 1, "y": 1}, "items": [{"x": 1, "y": 1, "y": 1, "color": "red", "shape": "square"}])"),
       "items[0]: duplicate key \"y\""},
  };
  for (const auto& c : cases) {
    INFO("world: " << c.json);
    try {
      (void)grid()->load(c.json, ".");
      FAIL("accepted");
    } catch (const sdk::Error& e) {
      INFO("message: " << e.what());
      CHECK(e.code() == sdk::codes::kBadWorld);
      CHECK(std::string(e.what()).find(c.names) != std::string::npos);
    }
  }
}
