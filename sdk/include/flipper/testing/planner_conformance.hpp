#pragma once
/// @file planner_conformance.hpp
/// Conformance checks for planner plugins (header-only, Catch2 v2; include <catch2/catch.hpp>
/// first), after OMPL's PlannerTest: on seeded random mazes (2-D, and 3-D when the traits claim
/// it) every path found is connected, enters only free cells and no avoided cell, ends in a goal
/// and — for planners whose traits say `optimal` — is as short as a reference breadth-first
/// search says, which also decides reachability; other planners must find a path to every
/// reachable goal (`sampling` ones: at least 9 in 10 within their budget); "no path" is a status,
/// never an exception; a stop condition that is already true stops at once; among equally near
/// goals every planner takes the smallest (x, y, z) (docs/core-language.md §8; checked with goals
/// that are mirror images of one another, so they tie under any symmetric distance);
/// `deterministic` planners answer the same twice and the same whatever they were asked before
/// (a fresh instance asked in reverse order agrees); tours are permutations with unreachable
/// points last in (x, y, z) order.
///
/// @code
///   FLIPPER_PLANNER_CONFORMANCE("astar", [] { return load_plugin<sdk::Planner>("astar"); })
/// @endcode

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "flipper/sdk/planner.hpp"

namespace flipper::testing {

using PlannerFactory = std::function<std::shared_ptr<sdk::Planner>()>;

/// A seeded random maze: the border is free, a fraction `walls` of the cells is blocked.
inline std::shared_ptr<const sdk::Geometry> random_maze(int dims, int sx, int sy, int sz,
                                                        double walls, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution wall(walls);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(sx) * sy * sz);
  for (auto& m : mask) m = wall(rng) ? 0 : 1;
  std::vector<sdk::Cell> offsets = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  if (dims == 3) {
    offsets.push_back({0, 0, 1});
    offsets.push_back({0, 0, -1});
  }
  return std::make_shared<const sdk::Geometry>(
      dims, sdk::Cell{-2, 3, 0}, sdk::Cell{sx - 3, sy + 2, sz - 1}, std::move(mask), offsets,
      std::vector<std::pair<std::string, sdk::Cell>>{{"right", {1, 0, 0}}});
}

/// Reference: breadth-first distance from `start` to the nearest free cell of `goals` avoiding
/// `avoid` (start exempt); -1 if none is reachable.
inline int reference_distance(const sdk::Geometry& g, sdk::Cell start, const sdk::Area& goals,
                              const sdk::Area& avoid) {
  auto passable = [&](const sdk::Cell& c) {
    return g.is_free(c) && !sdk::areas::contains(avoid, c);
  };
  std::vector<int> dist(g.cell_count(), -1);
  std::deque<sdk::Cell> q{start};
  dist[g.index(start)] = 0;
  while (!q.empty()) {
    const sdk::Cell u = q.front();
    q.pop_front();
    const int du = dist[g.index(u)];
    if (sdk::areas::contains(goals, u) && (g.is_free(u) || u == start)) return du;
    for (const sdk::Cell& o : g.neighbour_offsets()) {
      const sdk::Cell v = u + o;
      if (!passable(v) || dist[g.index(v)] >= 0) continue;
      dist[g.index(v)] = du + 1;
      q.push_back(v);
    }
  }
  return -1;
}

/// The path is a walk of neighbour steps from `start` over free, non-avoided cells ending at
/// the target, which is a goal.
inline void check_path_shape(const sdk::Geometry& g, const sdk::PathRequest& req,
                             const sdk::PathResult& r) {
  REQUIRE(r.status == sdk::PlanStatus::found);
  sdk::Cell at = req.start;
  for (const sdk::Cell& c : r.path) {
    const sdk::Cell step{c.x - at.x, c.y - at.y, c.z - at.z};
    const auto& offs = g.neighbour_offsets();
    REQUIRE(std::find(offs.begin(), offs.end(), step) != offs.end());
    REQUIRE(g.is_free(c));
    if (req.avoid != nullptr) REQUIRE(!sdk::areas::contains(*req.avoid, c));
    at = c;
  }
  REQUIRE(at == r.target);
  REQUIRE(sdk::areas::contains(*req.goals, r.target));
}

inline void check_random_requests(const sdk::Planner& planner, const sdk::Geometry& g,
                                  std::uint32_t seed, int requests) {
  const auto traits = planner.traits();
  const sdk::Area& free = g.free_cells();
  REQUIRE(!free.empty());
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> pick_free(0, free.size() - 1);
  std::uniform_int_distribution<std::size_t> pick_any(0, g.cell_count() - 1);
  int reachable = 0, found = 0;  // non-optimal planners: requests with a path, paths found
  for (int n = 0; n < requests; ++n) {
    const sdk::Cell start = free[pick_free(rng)];
    sdk::Area goals, avoid;
    const int goal_count = 1 + n % 4;
    for (int k = 0; k < goal_count; ++k) goals.push_back(g.cell_at(pick_any(rng)));
    for (int k = 0; k < n % 5 * 3; ++k) avoid.push_back(g.cell_at(pick_any(rng)));
    sdk::areas::normalize(goals);
    sdk::areas::normalize(avoid);
    const sdk::PathRequest req{start, &goals, avoid.empty() ? nullptr : &avoid};
    INFO("request " << n << " from " << sdk::to_string(start, g.dims()));
    sdk::PathResult r;
    REQUIRE_NOTHROW(r = planner.plan(g, req, sdk::StopCondition{}));
    const int expected = reference_distance(g, start, goals, avoid);
    if (traits.optimal) {
      if (expected < 0) {
        REQUIRE(r.status == sdk::PlanStatus::no_path);
        REQUIRE(!r.message.empty());
      } else {
        check_path_shape(g, req, r);
        REQUIRE(static_cast<int>(r.path.size()) == expected);
      }
    } else {
      if (expected < 0) REQUIRE(r.status != sdk::PlanStatus::found);
      if (expected >= 0) {
        ++reachable;
        // Only a sampling planner may miss a reachable goal (counted below).
        if (!traits.sampling) REQUIRE(r.status == sdk::PlanStatus::found);
      }
      if (r.status == sdk::PlanStatus::found) {
        ++found;
        check_path_shape(g, req, r);
      }
    }
    if (traits.deterministic) {
      const sdk::PathResult again = planner.plan(g, req, sdk::StopCondition{});
      REQUIRE(again.status == r.status);
      REQUIRE(again.path == r.path);
      if (r.status == sdk::PlanStatus::found) REQUIRE(again.target == r.target);
    }
  }
  // A planner that never (or seldom) finds a path fails here, sampling or not.
  INFO("non-optimal planner: " << found << " paths for " << reachable << " reachable requests");
  REQUIRE(found * 10 >= reachable * 9);
}

inline void check_tour(const sdk::Planner& planner, const sdk::Geometry& g, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const sdk::Area& free = g.free_cells();
  std::uniform_int_distribution<std::size_t> pick_free(0, free.size() - 1);
  std::uniform_int_distribution<std::size_t> pick_any(0, g.cell_count() - 1);
  const sdk::Cell start = free[pick_free(rng)];
  std::vector<sdk::Cell> points;
  for (int k = 0; k < 25; ++k) points.push_back(g.cell_at(pick_any(rng)));
  points.push_back(points.front());  // a duplicate point
  points.push_back(start);
  const sdk::TourResult t = planner.tour(g, start, points, sdk::StopCondition{});
  REQUIRE(t.status == sdk::PlanStatus::found);
  std::vector<std::size_t> sorted = t.order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> identity(points.size());
  std::iota(identity.begin(), identity.end(), 0);
  REQUIRE(sorted == identity);
  // Reachable points first, then the unreachable ones in (x, y, z) order.
  const sdk::Area self{start};
  std::size_t first_unreachable = t.order.size();
  for (std::size_t i = 0; i < t.order.size(); ++i) {
    const sdk::Cell c = points[t.order[i]];
    const bool reachable = reference_distance(g, c, self, {}) >= 0 && g.is_free(c);
    if (!reachable && first_unreachable == t.order.size()) first_unreachable = i;
    if (i >= first_unreachable) {
      REQUIRE(!reachable);
      if (i > first_unreachable) REQUIRE(points[t.order[i - 1]] <= c);
    }
  }
  if (planner.traits().deterministic) {
    const sdk::TourResult again = planner.tour(g, start, points, sdk::StopCondition{});
    REQUIRE(again.order == t.order);
    REQUIRE(again.length == t.length);
  }
  const sdk::TourResult none = planner.tour(g, start, {}, sdk::StopCondition{});
  REQUIRE(none.order.empty());
}

/// Two free regions separated by a wall: nothing in the right half is reachable from the left.
inline std::shared_ptr<const sdk::Geometry> split_map() {
  std::vector<std::uint8_t> mask(7 * 3, 1);
  for (int y = 0; y < 3; ++y) mask[static_cast<std::size_t>(3 + 7 * y)] = 0;
  return std::make_shared<const sdk::Geometry>(
      2, sdk::Cell{0, 0, 0}, sdk::Cell{6, 2, 0}, std::move(mask),
      std::vector<sdk::Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, sdk::Cell>>{});
}

/// The edge cases Planner::plan/tour decide for every planner: exact statuses,
/// messages and orders, whatever the plugin.
inline void check_planner_edge_cases(const sdk::Planner& planner) {
  const auto g = split_map();
  const sdk::Cell start{1, 1, 0};
  sdk::StopCondition fired;
  fired.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  const sdk::Area empty;
  for (const sdk::StopCondition& stop : {sdk::StopCondition{}, fired}) {
    // No goals is a bad request even when the stop has fired.
    sdk::PathResult r = planner.plan(*g, {start, &empty, nullptr}, stop);
    REQUIRE(r.status == sdk::PlanStatus::invalid);
    REQUIRE(r.message == "the goal set is empty");
    REQUIRE(r.path.empty());
    r = planner.plan(*g, {start, nullptr, nullptr}, stop);
    REQUIRE(r.status == sdk::PlanStatus::invalid);
    REQUIRE(r.message == "the goal set is empty");
    const sdk::Area goal{{0, 0, 0}};
    r = planner.plan(*g, {{40, 1, 0}, &goal, nullptr}, stop);
    REQUIRE(r.status == sdk::PlanStatus::invalid);
    REQUIRE(r.message == "start [40,1] is outside the bounds");
    // No points: nothing to order, found.
    const sdk::TourResult t = planner.tour(*g, start, {}, stop);
    REQUIRE(t.status == sdk::PlanStatus::found);
    REQUIRE(t.order.empty());
  }
  // A stop that has fired: stopped before any search, even for the start's own cell.
  const sdk::Area self{start};
  const sdk::PathResult r = planner.plan(*g, {start, &self, nullptr}, fired);
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  REQUIRE(r.message == "stopped before planning");
  REQUIRE(r.path.empty());
  // ... and a tour gives every point in (x, y, z) order, ties by index.
  const std::vector<sdk::Cell> pts{{5, 0, 0}, {0, 2, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 0}};
  const sdk::TourResult t = planner.tour(*g, start, pts, fired);
  REQUIRE(t.status == sdk::PlanStatus::stopped);
  REQUIRE(t.order == std::vector<std::size_t>{4, 1, 3, 2, 0});
}

inline void check_planner_basics(const sdk::Planner& planner) {
  const auto g = split_map();
  const sdk::Cell start{1, 1, 0};
  // A path to the own cell is empty.
  const sdk::Area self{start};
  sdk::PathResult r = planner.plan(*g, {start, &self, nullptr}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::found);
  REQUIRE(r.path.empty());
  REQUIRE(r.target == start);
  // Infeasible: a status with a message, not an exception.
  const sdk::Area right{{5, 1, 0}};
  REQUIRE_NOTHROW(r = planner.plan(*g, {start, &right, nullptr}, sdk::StopCondition{}));
  REQUIRE(r.status == sdk::PlanStatus::no_path);
  REQUIRE(!r.message.empty());
  // Goals on walls and outside the bounds are ignored.
  const sdk::Area walls{{3, 1, 0}, {40, 1, 0}};
  r = planner.plan(*g, {start, &walls, nullptr}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::no_path);
  // An empty goal set is a bad request, still not an exception.
  const sdk::Area empty;
  REQUIRE_NOTHROW(r = planner.plan(*g, {start, &empty, nullptr}, sdk::StopCondition{}));
  REQUIRE(r.status == sdk::PlanStatus::invalid);
  // A stop condition that is already true stops at once, for paths and tours.
  const sdk::Area far{{0, 0, 0}};
  sdk::StopCondition past;
  past.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  r = planner.plan(*g, {start, &far, nullptr}, past);
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  std::atomic<bool> cancel{true};
  sdk::StopCondition cancelled;
  cancelled.cancel = &cancel;
  r = planner.plan(*g, {start, &far, nullptr}, cancelled);
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  // A CPU budget already spent (docs/planners.md §2) stops as well.
  sdk::StopCondition spent;
  spent.cpu_clock = sdk::this_thread_cpu_clock();
  spent.cpu_deadline = sdk::cpu_time(spent.cpu_clock);
  REQUIRE(spent.cause() == sdk::StopCause::cpu_budget);
  r = planner.plan(*g, {start, &far, nullptr}, spent);
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  const std::vector<sdk::Cell> pts{{0, 0, 0}, {2, 2, 0}, {5, 0, 0}};
  const sdk::TourResult t = planner.tour(*g, start, pts, past);
  REQUIRE(t.status == sdk::PlanStatus::stopped);
  REQUIRE(t.order.size() == pts.size());
  check_planner_edge_cases(planner);
}

/// An open box (no walls) of `n` cells per side, 2-D or 3-D.
inline std::shared_ptr<const sdk::Geometry> open_box(int dims, int n) {
  const int nz = dims == 3 ? n : 1;
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(n) * n * nz, 1);
  std::vector<sdk::Cell> offsets = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  if (dims == 3) {
    offsets.push_back({0, 0, 1});
    offsets.push_back({0, 0, -1});
  }
  return std::make_shared<const sdk::Geometry>(
      dims, sdk::Cell{0, 0, 0}, sdk::Cell{n - 1, n - 1, nz - 1}, std::move(mask), offsets,
      std::vector<std::pair<std::string, sdk::Cell>>{});
}

/// The tie rule (docs/core-language.md §8; sdk/planner.hpp): among equally near goals the
/// smallest (x, y, z), i.e. the first of the sorted goal set, for every planner. Each case's
/// goals are mirror images of one another around the start on an open map, so they are equally
/// near by path, by straight line and by any distance that respects the grid's symmetry; a
/// planner keeping the last (or any other) of them fails, and so does one that lets a farther
/// but smaller goal win.
inline void check_goal_ties(const sdk::Planner& planner, int dims) {
  const int n = 11, c = 5;
  const auto g = open_box(dims, n);
  const int z = dims == 3 ? c : 0;
  const sdk::Cell start{c, c, z};
  struct Case {
    const char* what;
    sdk::Area goals;
    sdk::Cell want;
  };
  std::vector<Case> cases = {
      {"four goals 3 steps away along the axes",
       {{2, 5, z}, {8, 5, z}, {5, 2, z}, {5, 8, z}},
       {2, 5, z}},
      {"two goals that differ in y only", {{5, 8, z}, {5, 2, z}}, {5, 2, z}},
      {"eight goals at (+-2, +-1) and (+-1, +-2), and a farther smaller one",
       {{3, 4, z},
        {3, 6, z},
        {7, 4, z},
        {7, 6, z},
        {4, 3, z},
        {6, 3, z},
        {4, 7, z},
        {6, 7, z},
        {0, 5, z}},
       {3, 4, z}},
  };
  if (dims == 3) {
    cases.push_back({"two goals that differ in z only", {{5, 5, 8}, {5, 5, 2}}, {5, 5, 2}});
    cases.push_back({"six goals 2 steps away along the axes",
                     {{3, 5, 5}, {7, 5, 5}, {5, 3, 5}, {5, 7, 5}, {5, 5, 3}, {5, 5, 7}},
                     {3, 5, 5}});
  }
  for (Case& k : cases) {
    INFO("goal tie: " << k.what << " from " << sdk::to_string(start, dims));
    sdk::areas::normalize(k.goals);
    const sdk::PathRequest req{start, &k.goals, nullptr};
    const sdk::PathResult r = planner.plan(*g, req, sdk::StopCondition{});
    INFO("reached " << sdk::to_string(r.target, dims) << ", want " << sdk::to_string(k.want, dims));
    check_path_shape(*g, req, r);
    REQUIRE(r.target == k.want);
    if (planner.traits().optimal)
      REQUIRE(static_cast<int>(r.path.size()) == reference_distance(*g, start, k.goals, {}));
  }
}

/// Deterministic planners answer a request the same whatever they were asked before: `factory`
/// makes a second instance that answers the same requests (and tours) in reverse order.
inline void check_history_independence(const PlannerFactory& factory, const sdk::Geometry& g,
                                       std::uint32_t seed, int requests) {
  const auto first = factory();
  if (!first->traits().deterministic) return;
  const auto second = factory();
  std::mt19937 rng(seed);
  const sdk::Area& free = g.free_cells();
  std::uniform_int_distribution<std::size_t> pick_free(0, free.size() - 1);
  std::vector<std::pair<sdk::Cell, sdk::Area>> asked;
  for (int k = 0; k < requests; ++k) {
    sdk::Area goals{free[pick_free(rng)], free[pick_free(rng)]};
    sdk::areas::normalize(goals);
    asked.push_back({free[pick_free(rng)], std::move(goals)});
  }
  std::vector<sdk::Cell> points;
  for (int k = 0; k < 12; ++k) points.push_back(free[pick_free(rng)]);
  std::vector<sdk::PathResult> forward;
  for (const auto& [start, goals] : asked)
    forward.push_back(first->plan(g, {start, &goals, nullptr}, sdk::StopCondition{}));
  const sdk::TourResult tour_after = first->tour(g, free.front(), points, sdk::StopCondition{});
  const sdk::TourResult tour_before = second->tour(g, free.front(), points, sdk::StopCondition{});
  REQUIRE(tour_before.order == tour_after.order);
  for (std::size_t k = asked.size(); k-- > 0;) {
    INFO("request " << k << " asked last of " << asked.size() << ", then first");
    const auto& [start, goals] = asked[k];
    const sdk::PathResult r = second->plan(g, {start, &goals, nullptr}, sdk::StopCondition{});
    REQUIRE(r.status == forward[k].status);
    REQUIRE(r.path == forward[k].path);
    if (r.status == sdk::PlanStatus::found) REQUIRE(r.target == forward[k].target);
  }
}

/// Every check on the planner from `factory`.
inline void check_planner_conformance(const PlannerFactory& factory) {
  auto planner = factory();
  REQUIRE(planner != nullptr);
  const auto traits = planner->traits();
  check_planner_basics(*planner);
  if (traits.supports_2d) {
    check_goal_ties(*planner, 2);
    for (std::uint32_t seed : {1u, 2u, 3u}) {
      const auto g = random_maze(2, 24, 17, 1, 0.3, seed);
      check_random_requests(*planner, *g, seed, 60);
      check_tour(*planner, *g, seed);
    }
    check_history_independence(factory, *random_maze(2, 24, 17, 1, 0.3, 4), 4, 20);
  }
  if (traits.supports_3d) {
    check_goal_ties(*planner, 3);
    const auto g = random_maze(3, 9, 8, 7, 0.35, 11);
    check_random_requests(*planner, *g, 11, 60);
    check_tour(*planner, *g, 11);
    check_history_independence(factory, *g, 12, 20);
  }
}

}  // namespace flipper::testing

/// Defines a Catch2 test case running every planner check on the plugin from `factory`.
#define FLIPPER_PLANNER_CONFORMANCE(name, factory)                    \
  TEST_CASE(name ": planner conformance", "[conformance][planner]") { \
    ::flipper::testing::check_planner_conformance(factory);           \
  }
