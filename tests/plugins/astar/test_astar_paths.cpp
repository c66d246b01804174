#include <catch2/catch.hpp>

#include "astar_support.hpp"
#include "flipper/sdk/errors.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

sdk::PathResult plan(const sdk::Geometry& g, Cell start, const sdk::Area& goals,
                     const sdk::Area* avoid = nullptr) {
  return testsupport::astar()->plan(g, {start, &goals, avoid}, sdk::StopCondition{});
}

}  // namespace

TEST_CASE("study map: the nearest red item is five steps east", "[astar][study]") {
  const auto& w = testsupport::study_map();
  sdk::Area red;
  for (const auto& li : w.items)
    if (li.item.color == "red") red.push_back(li.at);
  sdk::areas::normalize(red);
  REQUIRE(red == sdk::Area{{4, 0, 0}, {7, 4, 0}, {10, 8, 0}});
  const auto r = plan(*w.geometry, w.robot, red);
  REQUIRE(r.status == sdk::PlanStatus::found);
  REQUIRE(r.target == Cell{7, 4, 0});
  REQUIRE(r.path == std::vector<Cell>{{3, 4, 0}, {4, 4, 0}, {5, 4, 0}, {6, 4, 0}, {7, 4, 0}});
}

TEST_CASE("study map: visit [9,8] while avoiding room3", "[astar][study]") {
  const auto& w = testsupport::study_map();
  const sdk::Area& room3 = w.rooms->at("room3");
  const sdk::Area target{{9, 8, 0}};
  const auto from_room3 = plan(*w.geometry, {2, 4, 0}, target, &room3);
  REQUIRE(from_room3.status == sdk::PlanStatus::no_path);
  REQUIRE(!from_room3.message.empty());
  const auto from_room5 = plan(*w.geometry, {7, 7, 0}, target, &room3);
  REQUIRE(from_room5.status == sdk::PlanStatus::found);
  REQUIRE(from_room5.path == std::vector<Cell>{{8, 7, 0}, {9, 7, 0}, {9, 8, 0}});
  // Without the avoid set the robot walks out of room3 through the opening at (5,6).
  const auto free_walk = plan(*w.geometry, {2, 4, 0}, target);
  REQUIRE(free_walk.status == sdk::PlanStatus::found);
  REQUIRE(free_walk.path.size() == 11);
}

TEST_CASE("equally near goals: the smallest x, then y, wins", "[astar][ties]") {
  const auto g = testsupport::grid_from_rows({".....", ".....", ".....", ".....", "....."});
  REQUIRE(plan(*g, {2, 2, 0}, {{0, 2, 0}, {2, 0, 0}, {2, 4, 0}, {4, 2, 0}}).target ==
          Cell{0, 2, 0});
  REQUIRE(plan(*g, {2, 2, 0}, {{2, 0, 0}, {2, 4, 0}, {4, 2, 0}}).target == Cell{2, 0, 0});
  REQUIRE(plan(*g, {2, 2, 0}, {{3, 3, 0}, {3, 1, 0}}).target == Cell{3, 1, 0});
  // A nearer goal beats a smaller one.
  REQUIRE(plan(*g, {2, 2, 0}, {{0, 0, 0}, {3, 2, 0}}).target == Cell{3, 2, 0});
}

TEST_CASE("equal paths: breadth-first order right, left, up, down", "[astar][ties]") {
  const auto g = testsupport::grid_from_rows({"...", "...", "..."});
  REQUIRE(plan(*g, {0, 0, 0}, {{2, 2, 0}}).path ==
          std::vector<Cell>{{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}});
  REQUIRE(plan(*g, {2, 2, 0}, {{0, 0, 0}}).path ==
          std::vector<Cell>{{1, 2, 0}, {0, 2, 0}, {0, 1, 0}, {0, 0, 0}});
  REQUIRE(plan(*g, {0, 2, 0}, {{2, 0, 0}}).path ==
          std::vector<Cell>{{1, 2, 0}, {2, 2, 0}, {2, 1, 0}, {2, 0, 0}});
}

TEST_CASE("avoid sets: the start is exempt, an avoided goal is unreachable", "[astar]") {
  const auto g = testsupport::grid_from_rows({"....", "....", "...."});
  const sdk::Area avoid{{0, 0, 0}, {1, 1, 0}, {2, 1, 0}};
  // Start inside the avoid set: it may leave it, but not through other avoided cells.
  const auto r = plan(*g, {0, 0, 0}, {{3, 1, 0}}, &avoid);
  REQUIRE(r.status == sdk::PlanStatus::found);
  REQUIRE(r.path == std::vector<Cell>{{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}});
  REQUIRE(plan(*g, {0, 2, 0}, {{1, 1, 0}}, &avoid).status == sdk::PlanStatus::no_path);
  // The start is a goal even when avoided.
  const auto here = plan(*g, {0, 0, 0}, {{0, 0, 0}}, &avoid);
  REQUIRE(here.status == sdk::PlanStatus::found);
  REQUIRE(here.path.empty());
}

TEST_CASE("walls and cells outside the bounds among the goals are ignored", "[astar]") {
  const auto g = testsupport::grid_from_rows({"..#", "...", "..."});
  const auto r = plan(*g, {0, 0, 0}, {{2, 2, 0}, {-1, 0, 0}, {9, 9, 0}, {0, 2, 0}});
  REQUIRE(r.status == sdk::PlanStatus::found);
  REQUIRE(r.target == Cell{0, 2, 0});
  REQUIRE(plan(*g, {0, 0, 0}, {{2, 2, 0}, {5, 0, 0}}).status == sdk::PlanStatus::no_path);
  REQUIRE(plan(*g, {7, 0, 0}, {{0, 0, 0}}).status == sdk::PlanStatus::invalid);
}

TEST_CASE("the expansion budget stops long searches", "[astar]") {
  const auto g = testsupport::grid_from_rows({"..........", ".........."});
  auto limited = testsupport::astar(sdk::Params({{"max_expansions", std::int64_t{3}}}));
  const sdk::Area far{{9, 1, 0}};
  const auto r = limited->plan(*g, {{0, 0, 0}, &far, nullptr}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  REQUIRE(r.expansions == 3);
  sdk::StopCondition budget;
  budget.max_expansions = 5;
  const auto s = testsupport::astar()->plan(*g, {{0, 0, 0}, &far, nullptr}, budget);
  REQUIRE(s.status == sdk::PlanStatus::stopped);
  REQUIRE(s.expansions == 5);
  const sdk::Area near{{1, 0, 0}};
  REQUIRE(limited->plan(*g, {{0, 0, 0}, &near, nullptr}, sdk::StopCondition{}).status ==
          sdk::PlanStatus::found);
}

TEST_CASE("paths in a 3-D world use its six neighbours", "[astar][3d]") {
  std::vector<std::uint8_t> mask(3 * 3 * 3, 1);
  mask[1 + 3 * (1 + 3 * 0)] = 0;  // (1,1,0) blocked
  const sdk::Geometry g(3, {0, 0, 0}, {2, 2, 2}, mask,
                        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}, {});
  const auto r = plan(g, {0, 0, 0}, {{0, 0, 2}});
  REQUIRE(r.path == std::vector<Cell>{{0, 0, 1}, {0, 0, 2}});
  const auto t = plan(g, {0, 0, 0}, {{2, 2, 0}, {1, 1, 1}});
  REQUIRE(t.status == sdk::PlanStatus::found);
  REQUIRE(t.path.size() == 3);
  REQUIRE(t.target == Cell{1, 1, 1});
}

TEST_CASE("the manhattan heuristic finds equally short paths to single cells", "[astar]") {
  auto bfs = testsupport::astar();
  auto astar = testsupport::astar(sdk::Params({{"heuristic", std::string("manhattan")}}));
  const auto& w = testsupport::study_map();
  for (const Cell& from : w.geometry->free_cells())
    for (const Cell& to : {Cell{9, 8, 0}, Cell{0, 0, 0}, Cell{11, 1, 0}}) {
      const sdk::Area goal{to};
      const auto a = astar->plan(*w.geometry, {from, &goal, nullptr}, sdk::StopCondition{});
      const auto b = bfs->plan(*w.geometry, {from, &goal, nullptr}, sdk::StopCondition{});
      REQUIRE(a.status == sdk::PlanStatus::found);
      REQUIRE(a.path.size() == b.path.size());
      REQUIRE(a.expansions <= b.expansions + 1);
    }
  REQUIRE_THROWS_AS(testsupport::astar(sdk::Params({{"heuristic", std::string("euclid")}})),
                    sdk::Error);
}
