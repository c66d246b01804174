#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <numeric>

#include "flipper/sdk/planner.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

TEST_CASE("ompl tour: nearest neighbour + 2-opt on straight lines, unreachable last",
          "[ompl][tour]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto planner = testsupport::load_plugin<sdk::Planner>("ompl");
  // Points along floor 0's room1 column x = 1, given out of order, plus a slab cell (blocked)
  // and a free cell cut off by nothing (floor 1) which is reachable.
  const std::vector<Cell> pts{{1, 7, 0}, {0, 0, 1}, {1, 3, 0}, {1, 5, 0}, {1, 2, 0}, {1, 1, 2}};
  const sdk::TourResult t = planner->tour(*s.geometry, s.robot, pts, sdk::StopCondition{});
  REQUIRE(t.status == sdk::PlanStatus::found);
  // Nearest neighbour from (1,1,0) walks up the column (1,2,0) ... (1,7,0), then (1,1,2), which
  // is only 2 away from the start in a straight line (straight lines ignore the slab). Visiting
  // it first would be shorter, but that is an Or-opt move, not a 2-opt one: the tour is the
  // 2-opt local optimum. The blocked slab cell comes last.
  const std::vector<std::size_t> expected{4, 2, 3, 0, 5, 1};
  REQUIRE(t.order == expected);
  REQUIRE(t.length > 0);
}

TEST_CASE("ompl tour: 2-opt removes crossings", "[ompl][tour]") {
  std::vector<std::uint8_t> mask(20 * 20, 1);
  const sdk::Geometry g(2, {0, 0, 0}, {19, 19, 0}, mask,
                        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {});
  // Nearest neighbour from (0,0) goes (1,0) -> (0,2)... a zig-zag that 2-opt straightens.
  const std::vector<Cell> pts{{10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {1, 1, 0}, {9, 1, 0}};
  auto planner = testsupport::load_plugin<sdk::Planner>("ompl");
  const sdk::TourResult t = planner->tour(g, {0, 0, 0}, pts, sdk::StopCondition{});
  // No two tour edges cross: total length is at most that of the obvious loop.
  double best = 0;
  Cell at{0, 0, 0};
  for (std::size_t i : std::vector<std::size_t>{3, 4, 0, 2, 1}) {
    const Cell c = pts[i];
    best += std::hypot(c.x - at.x, c.y - at.y);
    at = c;
  }
  REQUIRE(t.length <= best + 1e-9);
}

TEST_CASE(
    "ompl tour: a stop mid-tour is `stopped` in (x, y, z) order, never a shorter-worked order",
    "[ompl][tour]") {
  // A runaway deadline or a cancel may cut the tour anywhere (docs/planners.md §2): the answer is
  // then either the full tour (it finished first) or `stopped` with every point in (x, y, z)
  // order, whatever the moment. A 2-opt cut short and returned as `found` fails here.
  std::vector<std::uint8_t> mask(200 * 200, 1);
  const sdk::Geometry g(2, {0, 0, 0}, {199, 199, 0}, mask,
                        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}}, {});
  std::vector<Cell> pts;
  std::uint32_t x = 12345;  // a fixed pseudo-random scatter (xorshift)
  for (int k = 0; k < 1500; ++k) {
    x ^= x << 13, x ^= x >> 17, x ^= x << 5;
    pts.push_back(
        {static_cast<std::int32_t>(x % 200), static_cast<std::int32_t>((x >> 8) % 200), 0});
  }
  auto planner = testsupport::load_plugin<sdk::Planner>("ompl");
  const auto t0 = std::chrono::steady_clock::now();
  const sdk::TourResult full = planner->tour(g, {0, 0, 0}, pts, sdk::StopCondition{});
  const auto took = std::chrono::steady_clock::now() - t0;
  REQUIRE(full.status == sdk::PlanStatus::found);
  std::vector<std::size_t> sorted(pts.size());
  std::iota(sorted.begin(), sorted.end(), 0);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](std::size_t a, std::size_t b) { return pts[a] < pts[b]; });
  for (const int percent : {10, 50, 90}) {
    INFO("deadline at " << percent << "% of an unstopped tour's time");
    const sdk::StopCondition stop = sdk::StopCondition::within(
        std::chrono::duration_cast<std::chrono::milliseconds>(took * percent / 100));
    const sdk::TourResult cut = planner->tour(g, {0, 0, 0}, pts, stop);
    if (cut.status == sdk::PlanStatus::found) {
      REQUIRE(cut.order == full.order);
    } else {
      REQUIRE(cut.status == sdk::PlanStatus::stopped);
      REQUIRE(cut.order == sorted);
    }
  }
}
