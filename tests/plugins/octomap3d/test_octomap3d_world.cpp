#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

std::size_t free_count(const sdk::Geometry& g) {
  return g.free_cells().size();
}

// One floor, z = 0 only, with a wall x = 4 (y 0..4): bodies of different sizes.
const char* kOneFloor = R"({
  "bounds": {"min": [0, 0, 0], "max": [8, 4, 0]},
  "boxes": [{"min": [4, 0, 0], "max": [4, 4, 0]}],
  "robot": {"x": 1, "y": 2, "z": 0}
})";

void require_bad(const std::string& json, const std::string& names, const sdk::Params& p = {}) {
  INFO(json);
  try {
    (void)testsupport::octomap_world(p)->load(json, testsupport::worlds_dir());
    FAIL("accepted");
  } catch (const sdk::Error& e) {
    INFO(e.what());
    REQUIRE(e.code() == sdk::codes::kBadWorld);
    REQUIRE(std::string(e.what()).find(names) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("octomap3d: two-floors world loads with the documented layout", "[octomap3d]") {
  const sdk::WorldState s = testsupport::two_floors();
  const sdk::Geometry& g = *s.geometry;
  REQUIRE(g.dims() == 3);
  REQUIRE(g.min() == Cell{0, 0, 0});
  REQUIRE(g.max() == Cell{9, 7, 2});
  // 240 cells - 79 slab cells (80 minus the shaft) - 7 wall cells on floor 0 - 9 on floor 1.
  REQUIRE(free_count(g) == 145);
  REQUIRE(g.is_free({8, 1, 1}));   // the shaft
  REQUIRE(!g.is_free({7, 1, 1}));  // slab
  REQUIRE(g.is_free({4, 3, 0}));   // door on floor 0
  REQUIRE(!g.is_free({4, 2, 0}));
  REQUIRE(g.is_free({2, 4, 2}));  // door on floor 1
  REQUIRE(!g.is_free({3, 4, 2}));
  REQUIRE(s.robot == Cell{1, 1, 0});
  REQUIRE(s.items.size() == 6);
  REQUIRE(s.items[3].at == Cell{1, 1, 2});
  REQUIRE(s.items[3].item.id == 3);
  REQUIRE(s.next_item_id == 6);
  REQUIRE(s.rooms->size() == 4);
  REQUIRE(s.rooms->at("room1").size() == 32);
  REQUIRE(s.rooms->at("room4").size() == 30);
}

TEST_CASE("octomap3d: neighbours +x,-x,+y,-y,+z,-z and plan-view directions", "[octomap3d]") {
  const sdk::WorldState s = testsupport::two_floors();
  const sdk::Geometry& g = *s.geometry;
  const std::vector<Cell> expected{{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                   {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  REQUIRE(g.neighbour_offsets() == expected);
  REQUIRE(g.direction("up") == Cell{0, 1, 0});
  REQUIRE(g.direction("down") == Cell{0, -1, 0});
  REQUIRE(g.direction("left") == Cell{-1, 0, 0});
  REQUIRE(g.direction("right") == Cell{1, 0, 0});
  REQUIRE(g.direction("ascend") == Cell{0, 0, 1});
  REQUIRE(g.direction("descend") == Cell{0, 0, -1});
  REQUIRE(!g.direction("north"));
  REQUIRE(testsupport::octomap_world()->dims() == 3);
}

TEST_CASE("octomap3d: the continuous space checks the body with FCL", "[octomap3d]") {
  const sdk::WorldState s = testsupport::two_floors();
  const sdk::ContinuousSpace* space = s.geometry->continuous();
  REQUIRE(space != nullptr);
  const double free_centre[3] = {1, 1, 0}, slab[3] = {0, 0, 1}, shaft[3] = {8, 1, 1};
  REQUIRE(space->is_state_valid(free_centre));
  REQUIRE(!space->is_state_valid(slab));
  REQUIRE(space->is_state_valid(shaft));
  // The 0.5 box fits 0.2 off centre but not 0.3 towards the wall x = 4 (which starts at 3.5).
  const double near_wall[3] = {3.2, 1, 0}, touching[3] = {3.3, 1, 0};
  REQUIRE(space->is_state_valid(near_wall));
  REQUIRE(!space->is_state_valid(touching));
  const double outside[3] = {-0.6, 1, 0};
  REQUIRE(!space->is_state_valid(outside));
  const double below[3] = {8, 1, 0}, above[3] = {8, 1, 2}, beside_below[3] = {7, 1, 0},
               beside_above[3] = {7, 1, 2};
  REQUIRE(space->is_motion_valid(below, above));                 // up the shaft
  REQUIRE(!space->is_motion_valid(beside_below, beside_above));  // through the slab
  const double a[3] = {1, 1, 0}, b[3] = {1, 6, 0};
  REQUIRE(space->is_motion_valid(a, b));
  const double c[3] = {3, 1, 0}, d[3] = {5, 1, 0};
  REQUIRE(!space->is_motion_valid(c, d));  // through the wall x = 4
}

TEST_CASE("octomap3d: the body decides which cells are free", "[octomap3d]") {
  auto load = [](const sdk::Params& p) {
    return testsupport::octomap_world(p)->load(kOneFloor, ".");
  };
  const auto small = load({});
  REQUIRE(free_count(*small.geometry) == 45 - 5);
  REQUIRE(small.geometry->is_free({3, 2, 0}));
  // A 1.5 m box overlaps the voxels next to its cell: cells beside the wall are blocked.
  const auto big = load(sdk::Params({{"body_size", 1.5}}));
  REQUIRE(!big.geometry->is_free({3, 2, 0}));
  REQUIRE(!big.geometry->is_free({5, 2, 0}));
  REQUIRE(big.geometry->is_free({2, 2, 0}));
  REQUIRE(free_count(*big.geometry) == 45 - 5 - 10);
  // A sphere of diameter 1.5 reaches the wall face but not (in the corner sense) diagonals:
  // beside the wall it collides, two cells away it does not.
  const auto sphere = load(sdk::Params({{"body", std::string("sphere")}, {"body_size", 1.5}}));
  REQUIRE(!sphere.geometry->is_free({3, 2, 0}));
  REQUIRE(sphere.geometry->is_free({2, 2, 0}));
  const auto thin = load(sdk::Params({{"body", std::string("sphere")}, {"body_size", 0.9}}));
  REQUIRE(thin.geometry->free_mask() == small.geometry->free_mask());
}

TEST_CASE("octomap3d: a robot in collision is refused", "[octomap3d]") {
  // With a 1.5 m box every floor-0 cell touches the slab above it.
  require_bad(testsupport::two_floors_json(), "robot (1,1,0) collides",
              sdk::Params({{"body_size", 1.5}}));
  require_bad(
      R"({"boxes": [{"min": [0, 0, 0], "max": [2, 2, 2]}], "robot": {"x": 1, "y": 1, "z": 1}})",
      "robot (1,1,1) collides");
}

TEST_CASE("octomap3d: malformed 3-D worlds name the offending entry", "[octomap3d]") {
  require_bad(
      R"({"boxes": [{"min": [0, 0], "max": [1, 1, 1]}], "robot": {"x": 0, "y": 0, "z": 0}})",
      "boxes[0].min is a 2-D point");
  require_bad(
      R"({"boxes": [{"min": [2, 0, 0], "max": [1, 1, 1]}], "robot": {"x": 0, "y": 0, "z": 0}})",
      "boxes[0] has min > max");
  require_bad(R"({"boxes": {"min": [0, 0, 0]}, "robot": {"x": 0, "y": 0, "z": 0}})", "boxes");
  require_bad(R"({"walls": [[1, 2]], "robot": {"x": 0, "y": 0, "z": 0}})", "walls[0]");
  require_bad(R"({"rooms": {"room1": [[1, 2]]}, "robot": {"x": 0, "y": 0, "z": 0}})", "room1");
  require_bad(R"({"robot": {"x": 0, "y": 0}})", "robot");
  require_bad(R"({"boxs": [], "robot": {"x": 0, "y": 0, "z": 0}})", "unknown entry \"boxs\"");
  require_bad(R"({"octomap": "no-such-file.bt", "robot": {"x": 0, "y": 0, "z": 0}})",
              "cannot read file");
  require_bad(R"({"bounds": {"min": [0, 0, 0], "max": [3, 3, 3]}, "robot": {"x": 0, "y": 0, "z": 0},
                  "items": [{"x": 9, "y": 0, "z": 0, "color": "red", "shape": "circle"}]})",
              "items[0]");
}

TEST_CASE("octomap3d: bad parameters are bad_config", "[octomap3d]") {
  try {
    (void)testsupport::octomap_world(sdk::Params({{"body", std::string("cone")}}));
    FAIL("accepted");
  } catch (const sdk::Error& e) {
    REQUIRE(e.code() == sdk::codes::kBadConfig);
    REQUIRE(std::string(e.what()).find("cone") != std::string::npos);
  }
}

TEST_CASE("octomap3d: save writes boxes, bounds and the state", "[octomap3d]") {
  auto world = testsupport::octomap_world();
  sdk::WorldState s = world->load(testsupport::two_floors_json(), testsupport::worlds_dir());
  s.robot = {8, 1, 2};
  s.held.push_back(s.items.front().item);
  s.items.erase(s.items.begin());
  const std::string saved = world->save(s);
  REQUIRE(saved.find("\"boxes\"") != std::string::npos);
  const sdk::WorldState t = world->load(saved, ".");
  REQUIRE(t.robot == Cell{8, 1, 2});
  REQUIRE(t.held == s.held);
  REQUIRE(t.items == s.items);
  REQUIRE(t.geometry->free_mask() == s.geometry->free_mask());
  REQUIRE(t.next_item_id == s.next_item_id);
}
