// The astar plugin on the 3-D world: breadth-first search over the 6-neighbourhood, through the
// shaft between the floors, with the reference distances of the planner conformance kit.
#include <catch2/catch.hpp>

#include "flipper/testing/planner_conformance.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

TEST_CASE("astar on octomap3d: shortest path between floors via the shaft", "[octomap3d][astar]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto astar = testsupport::load_plugin<sdk::Planner>("astar");
  REQUIRE(astar->traits().supports_3d);
  const sdk::Area& room4 = s.rooms->at("room4");
  const sdk::PathRequest req{s.robot, &room4, nullptr};
  const sdk::PathResult r = astar->plan(*s.geometry, req, sdk::StopCondition{});
  testing::check_path_shape(*s.geometry, req, r);
  // (1,1,0) -> door (4,3,0): 5, -> (8,1,0): 6, shaft: 2, -> door (2,4,2): 9, -> (2,5,2): 1.
  REQUIRE(r.path.size() == 23);
  REQUIRE(r.target == Cell{2, 5, 2});
  REQUIRE(testing::reference_distance(*s.geometry, s.robot, room4, {}) == 23);
  REQUIRE(std::find(r.path.begin(), r.path.end(), Cell{8, 1, 1}) != r.path.end());
}

TEST_CASE("astar on octomap3d: avoiding room2 cuts floor 1 off", "[octomap3d][astar]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto astar = testsupport::load_plugin<sdk::Planner>("astar");
  const sdk::PathRequest req{s.robot, &s.rooms->at("room4"), &s.rooms->at("room2")};
  const sdk::PathResult r = astar->plan(*s.geometry, req, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::no_path);
}

TEST_CASE("astar on octomap3d: random requests agree with the reference BFS",
          "[octomap3d][astar]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto astar = testsupport::load_plugin<sdk::Planner>("astar");
  testing::check_random_requests(*astar, *s.geometry, 7, 80);
  testing::check_tour(*astar, *s.geometry, 7);
}
