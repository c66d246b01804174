#include <catch2/catch.hpp>
#include <numeric>
#include <random>

#include "astar_support.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

// Length of visiting `points` in `order` from `start`, measured with the planner's own paths.
double walked_length(const sdk::Planner& p, const sdk::Geometry& g, Cell start,
                     const std::vector<Cell>& points, const std::vector<std::size_t>& order) {
  double total = 0;
  Cell at = start;
  for (std::size_t i : order) {
    const sdk::Area goal{points[i]};
    const auto r = p.plan(g, {at, &goal, nullptr}, sdk::StopCondition{});
    if (r.status != sdk::PlanStatus::found) break;  // unreachable points come last
    total += static_cast<double>(r.path.size());
    at = points[i];
  }
  return total;
}

bool is_permutation_of(const std::vector<std::size_t>& order, std::size_t n) {
  std::vector<std::size_t> s = order;
  std::sort(s.begin(), s.end());
  std::vector<std::size_t> id(n);
  std::iota(id.begin(), id.end(), 0);
  return s == id;
}

/// A tour instance: a w x h grid with walls drawn at rate `walls`, a free start and `n` free
/// points (repeats allowed), all drawn from one generator seeded with `seed`.
struct RandomTour {
  std::shared_ptr<const sdk::Geometry> grid;
  Cell start;
  std::vector<Cell> points;
};

RandomTour random_tour(std::uint32_t seed, int w, int h, double walls, int n) {
  std::mt19937 rng(seed);
  std::vector<std::string> rows(static_cast<std::size_t>(h),
                                std::string(static_cast<std::size_t>(w), '.'));
  std::bernoulli_distribution wall(walls);
  for (auto& r : rows)
    for (auto& c : r)
      if (wall(rng)) c = '#';
  RandomTour t{testsupport::grid_from_rows(rows), {}, {}};
  const auto& free = t.grid->free_cells();
  std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
  t.start = free[pick(rng)];
  for (int k = 0; k < n; ++k) t.points.push_back(free[pick(rng)]);
  return t;
}

}  // namespace

TEST_CASE("study map: foreach point in room3 starts at the robot", "[astar][tour][study]") {
  const auto& w = testsupport::study_map();
  const sdk::Area& room3 = w.rooms->at("room3");
  const std::vector<Cell> points(room3.begin(), room3.end());
  auto planner = testsupport::astar();
  const auto t = planner->tour(*w.geometry, w.robot, points, sdk::StopCondition{});
  REQUIRE(t.status == sdk::PlanStatus::found);
  REQUIRE(is_permutation_of(t.order, points.size()));
  REQUIRE(points[t.order.front()] == w.robot);  // (2,4) lies in room3: visited first
  REQUIRE(t.length == walked_length(*planner, *w.geometry, w.robot, points, t.order));
  // 32 cells, all reachable, one at the start: at least 31 steps.
  REQUIRE(t.length >= 31);
  REQUIRE(t.length <= 40);
}

TEST_CASE("tours put unreachable points last in (x, y) order", "[astar][tour]") {
  const auto g = testsupport::grid_from_rows({"....#.", "....#.", "....##"});
  const std::vector<Cell> points{{5, 2, 0}, {3, 0, 0}, {4, 1, 0}, {0, 2, 0},
                                 {5, 1, 0}, {9, 9, 0}, {1, 1, 0}};
  const auto t = testsupport::astar()->tour(*g, {2, 1, 0}, points, sdk::StopCondition{});
  REQUIRE(t.status == sdk::PlanStatus::found);
  REQUIRE(is_permutation_of(t.order, points.size()));
  const std::vector<std::size_t> tail(t.order.end() - 4, t.order.end());
  REQUIRE(tail == std::vector<std::size_t>{2, 4, 0, 5});  // (4,1) (5,1) (5,2) (9,9)
}

TEST_CASE("tour ties are broken by (x, y) order", "[astar][tour][ties]") {
  const auto g = testsupport::grid_from_rows({"......."});
  const std::vector<Cell> points{{6, 0, 0}, {0, 0, 0}};
  const auto t = testsupport::astar()->tour(*g, {3, 0, 0}, points, sdk::StopCondition{});
  REQUIRE(t.order == std::vector<std::size_t>{1, 0});
  REQUIRE(t.length == 9);
}

TEST_CASE("points sharing a cell stay together, in their order", "[astar][tour]") {
  const auto g = testsupport::grid_from_rows({"....."});
  const std::vector<Cell> points{{4, 0, 0}, {1, 0, 0}, {4, 0, 0}, {2, 0, 0}};
  const auto t = testsupport::astar()->tour(*g, {0, 0, 0}, points, sdk::StopCondition{});
  REQUIRE(t.order == std::vector<std::size_t>{1, 3, 0, 2});
  REQUIRE(t.length == 4);
}

TEST_CASE("2-opt and Or-opt never lengthen the Christofides tour", "[astar][tour]") {
  auto improved = testsupport::astar();
  auto plain = testsupport::astar(sdk::Params({{"two_opt", false}, {"or_opt", false}}));
  int strictly_better = 0;
  for (std::uint32_t seed = 1; seed <= 13; ++seed) {
    // The last instance has more than 200 points: Or-opt then uses neighbour lists.
    const bool large = seed == 13;
    const auto [g, start, points] =
        random_tour(seed, large ? 50 : 30, large ? 40 : 20, 0.25, large ? 300 : 40);
    const auto a = improved->tour(*g, start, points, sdk::StopCondition{});
    const auto b = plain->tour(*g, start, points, sdk::StopCondition{});
    REQUIRE(is_permutation_of(a.order, points.size()));
    REQUIRE(is_permutation_of(b.order, points.size()));
    REQUIRE(a.length <= b.length);
    REQUIRE(a.length == walked_length(*improved, *g, start, points, a.order));
    REQUIRE(b.length == walked_length(*plain, *g, start, points, b.order));
    if (a.length < b.length) ++strictly_better;
  }
  REQUIRE(strictly_better > 0);
}

TEST_CASE("tours over more than max_tour_points points go greedily to the nearest",
          "[astar][tour]") {
  auto greedy = testsupport::astar(sdk::Params({{"max_tour_points", std::int64_t{2}}}));
  const auto g = testsupport::grid_from_rows({"..........", "########.#"});
  // Robot at (4,1); (0,0) is a wall, so last. Nearest first: (5,1), then (2,1) and (1,1) back west
  // (3 and 1 steps), then (8,1) and (8,0) east.
  const std::vector<Cell> points{{8, 0, 0}, {1, 1, 0}, {5, 1, 0}, {0, 0, 0}, {2, 1, 0}, {8, 1, 0}};
  const auto t = greedy->tour(*g, {4, 1, 0}, points, sdk::StopCondition{});
  REQUIRE(t.status == sdk::PlanStatus::found);
  REQUIRE(t.order == std::vector<std::size_t>{2, 4, 1, 5, 0, 3});
  REQUIRE(t.length == 1 + 3 + 1 + 7 + 1);
  REQUIRE(t.length == walked_length(*greedy, *g, {4, 1, 0}, points, t.order));
  sdk::StopCondition past;
  past.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  REQUIRE(greedy->tour(*g, {4, 1, 0}, points, past).status == sdk::PlanStatus::stopped);
}

TEST_CASE("small tours are close to the best open path", "[astar][tour]") {
  auto planner = testsupport::astar();
  int optimal = 0;
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto [g, start, points] = random_tour(seed, 16, 12, 0.2, 6);
    const auto t = planner->tour(*g, start, points, sdk::StopCondition{});
    // The best open path over the reachable points, by trying every order.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const sdk::Area goal{points[i]};
      if (planner->plan(*g, {start, &goal, nullptr}, sdk::StopCondition{}).status ==
          sdk::PlanStatus::found)
        order.push_back(i);
    }
    double best = 1e18;
    do {
      best = std::min(best, walked_length(*planner, *g, start, points, order));
    } while (std::next_permutation(order.begin(), order.end()));
    INFO("seed " << seed);
    REQUIRE(t.length >= best);
    REQUIRE(t.length <= 1.5 * best);
    if (t.length == best) ++optimal;
  }
  REQUIRE(optimal >= 15);
}

TEST_CASE("remembered distances change no tour, and a changed map forgets them",
          "[astar][tour][cache]") {
  // The oracle: a planner under an expansion budget too large to bind, which never uses the
  // distance cache (astar_plugin.cpp), against one planner that serves every request in turn.
  auto uncached =
      testsupport::astar(sdk::Params({{"max_expansions", std::int64_t{1000000000000}}}));
  auto warm = testsupport::astar();
  auto same = [&](const sdk::Geometry& g, Cell start, const std::vector<Cell>& points) {
    const auto a = warm->tour(g, start, points, sdk::StopCondition{});
    const auto b = uncached->tour(g, start, points, sdk::StopCondition{});
    REQUIRE(a.status == sdk::PlanStatus::found);
    CHECK(a.order == b.order);
    CHECK(a.length == b.length);
  };
  for (std::uint32_t seed = 1; seed <= 30; ++seed) {
    const auto t = random_tour(seed, 24, 18, 0.25, 12);
    const auto& free = t.grid->free_cells();
    same(*t.grid, t.start, t.points);
    // Half the points again plus new ones, from another start: pairs partly remembered.
    std::vector<Cell> mixed(t.points.begin(), t.points.begin() + 6);
    for (std::size_t k = 0; k < 6; ++k) mixed.push_back(free[(seed * 7 + k * 13) % free.size()]);
    same(*t.grid, free[(seed * 31) % free.size()], mixed);
    same(*t.grid, t.start, t.points);  // every pair remembered
    // The same box with every wall opened: shorter distances between the same points.
    std::vector<std::uint8_t> open(t.grid->free_mask().size(), 1);
    const sdk::Geometry opened(2, t.grid->min(), t.grid->max(), std::move(open),
                               t.grid->neighbour_offsets(), {});
    same(opened, t.start, t.points);
  }
}
