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
/// points last in (x, y, z) order; two instances planning at once on two threads answer as one
/// alone (the threading rule of flipper/sdk/plugin.hpp). Paths and tours are judged by the kernel's
/// own check (flipper/sdk/answer_check.hpp), and every failure names its scenario: what was asked,
/// what came back and what is wrong with it.
///
/// @code
///   FLIPPER_PLANNER_CONFORMANCE("astar", [] { return load_plugin<sdk::Planner>("astar"); })
/// @endcode

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <latch>
#include <memory>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "flipper/sdk/answer_check.hpp"
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

/// Cells in words for a failure message: "[0,0] [5,1]", the first `most` of them and a count.
inline std::string describe_cells(const std::vector<sdk::Cell>& cells, int dims,
                                  std::size_t most = 8) {
  std::ostringstream s;
  for (std::size_t i = 0; i < cells.size() && i < most; ++i)
    s << (i == 0 ? "" : " ") << sdk::to_string(cells[i], dims);
  if (cells.size() > most) s << " ... (" << cells.size() << " cells)";
  if (cells.empty()) s << "nothing";
  return s.str();
}

/// A path request in words: "from [1,1] to [0,0] [5,1] avoiding [2,2]".
inline std::string describe_request(const sdk::Geometry& g, const sdk::PathRequest& req) {
  std::ostringstream s;
  s << "from " << sdk::to_string(req.start, g.dims()) << " to "
    << (req.goals == nullptr ? std::string("(no goal set)") : describe_cells(*req.goals, g.dims()));
  if (req.avoid != nullptr) s << " avoiding " << describe_cells(*req.avoid, g.dims());
  return s.str();
}

/// A planner's answer in words: "found [5,1] by 6 steps: [1,2] [2,2] ...", "no_path (why)".
inline std::string describe_answer(const sdk::Geometry& g, const sdk::PathResult& r) {
  std::ostringstream s;
  s << sdk::to_string(r.status);
  if (r.status == sdk::PlanStatus::found)
    s << " " << sdk::to_string(r.target, g.dims()) << " by " << r.path.size()
      << " steps: " << describe_cells(r.path, g.dims(), 12);
  if (!r.message.empty()) s << " (" << r.message << ")";
  return s.str();
}

/// A tour's order in words: "[2,0,1]".
inline std::string describe_order(const std::vector<std::size_t>& order) {
  std::ostringstream s;
  s << "[";
  for (std::size_t i = 0; i < order.size(); ++i) s << (i == 0 ? "" : ",") << order[i];
  s << "]";
  return s.str();
}

/// The path is found, and the kernel's check (sdk::path_violation) accepts it: a walk of
/// neighbour steps from `start` over free, non-avoided cells ending at the target, which is a
/// goal.
inline void check_path_shape(const sdk::Geometry& g, const sdk::PathRequest& req,
                             const sdk::PathResult& r) {
  INFO("asked: a path " << describe_request(g, req));
  INFO("answered: " << describe_answer(g, r));
  REQUIRE(r.status == sdk::PlanStatus::found);
  const std::optional<std::string> wrong = sdk::path_violation(g, req, r);
  INFO("what is wrong: " << wrong.value_or("nothing"));
  REQUIRE_FALSE(wrong.has_value());
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
    INFO("random request " << n << " (seed " << seed << "): a path " << describe_request(g, req));
    sdk::PathResult r;
    REQUIRE_NOTHROW(r = planner.plan(g, req, sdk::StopCondition{}));
    INFO("answered: " << describe_answer(g, r));
    const int expected = reference_distance(g, start, goals, avoid);
    INFO("breadth-first reference: " << (expected < 0 ? std::string("no path")
                                                      : std::to_string(expected) + " steps"));
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
      INFO("asked again (a deterministic planner): " << describe_answer(g, again));
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
  INFO("asked (seed " << seed << "): a tour from " << sdk::to_string(start, g.dims()) << " over "
                      << describe_cells(points, g.dims(), 30));
  const sdk::TourResult t = planner.tour(g, start, points, sdk::StopCondition{});
  INFO("answered: " << sdk::to_string(t.status) << ", order " << describe_order(t.order));
  REQUIRE(t.status == sdk::PlanStatus::found);
  const std::optional<std::string> wrong = sdk::tour_violation(points.size(), t);
  INFO("what is wrong: " << wrong.value_or("nothing"));
  REQUIRE_FALSE(wrong.has_value());
  // Reachable points first, then the unreachable ones in (x, y, z) order.
  const sdk::Area self{start};
  std::size_t first_unreachable = t.order.size();
  for (std::size_t i = 0; i < t.order.size(); ++i) {
    const sdk::Cell c = points[t.order[i]];
    const bool reachable = reference_distance(g, c, self, {}) >= 0 && g.is_free(c);
    if (!reachable && first_unreachable == t.order.size()) first_unreachable = i;
    INFO("position " << i << " of the order: point " << t.order[i] << " "
                     << sdk::to_string(c, g.dims()) << (reachable ? ", reachable" : ", unreachable")
                     << "; unreachable points must come last, in (x, y, z) order");
    if (i >= first_unreachable) {
      REQUIRE(!reachable);
      if (i > first_unreachable) REQUIRE(points[t.order[i - 1]] <= c);
    }
  }
  if (planner.traits().deterministic) {
    const sdk::TourResult again = planner.tour(g, start, points, sdk::StopCondition{});
    INFO("asked again (a deterministic planner): order " << describe_order(again.order)
                                                         << ", length " << again.length);
    REQUIRE(again.order == t.order);
    REQUIRE(again.length == t.length);
  }
  const sdk::TourResult none = planner.tour(g, start, {}, sdk::StopCondition{});
  INFO("asked: a tour over no points; answered order " << describe_order(none.order));
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
    INFO("edge cases on the split map, with "
         << (stop.expired() ? "a stop that has already fired" : "no stop condition"));
    // No goals is a bad request even when the stop has fired.
    {
      const sdk::PathRequest req{start, &empty, nullptr};
      const sdk::PathResult r = planner.plan(*g, req, stop);
      INFO("asked: a path " << describe_request(*g, req) << "; answered: " << describe_answer(*g, r)
                            << "; want: invalid (the goal set is empty)");
      REQUIRE(r.status == sdk::PlanStatus::invalid);
      REQUIRE(r.message == "the goal set is empty");
      REQUIRE(r.path.empty());
    }
    {
      const sdk::PathResult r = planner.plan(*g, {start, nullptr, nullptr}, stop);
      INFO("asked: a path from [1,1] with no goal set (null); answered: "
           << describe_answer(*g, r) << "; want: invalid (the goal set is empty)");
      REQUIRE(r.status == sdk::PlanStatus::invalid);
      REQUIRE(r.message == "the goal set is empty");
    }
    {
      const sdk::Area goal{{0, 0, 0}};
      const sdk::PathRequest req{{40, 1, 0}, &goal, nullptr};
      const sdk::PathResult r = planner.plan(*g, req, stop);
      INFO("asked: a path " << describe_request(*g, req) << " (a start outside the bounds); "
                            << "answered: " << describe_answer(*g, r)
                            << "; want: invalid (start [40,1] is outside the bounds)");
      REQUIRE(r.status == sdk::PlanStatus::invalid);
      REQUIRE(r.message == "start [40,1] is outside the bounds");
    }
    // No points: nothing to order, found.
    {
      const sdk::TourResult t = planner.tour(*g, start, {}, stop);
      INFO("asked: a tour from [1,1] over no points; answered: "
           << sdk::to_string(t.status) << ", order " << describe_order(t.order)
           << "; want: found, an empty order");
      REQUIRE(t.status == sdk::PlanStatus::found);
      REQUIRE(t.order.empty());
    }
  }
  // A stop that has fired: stopped before any search, even for the start's own cell.
  {
    const sdk::Area self{start};
    const sdk::PathResult r = planner.plan(*g, {start, &self, nullptr}, fired);
    INFO("asked: a path from [1,1] to [1,1] with a stop that has already fired; answered: "
         << describe_answer(*g, r) << "; want: stopped (stopped before planning), no path");
    REQUIRE(r.status == sdk::PlanStatus::stopped);
    REQUIRE(r.message == "stopped before planning");
    REQUIRE(r.path.empty());
  }
  // ... and a tour gives every point in (x, y, z) order, ties by index.
  const std::vector<sdk::Cell> pts{{5, 0, 0}, {0, 2, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 0}};
  const sdk::TourResult t = planner.tour(*g, start, pts, fired);
  INFO("asked: a tour from [1,1] over "
       << describe_cells(pts, 2)
       << " with a stop that has already fired; answered: " << sdk::to_string(t.status)
       << ", order " << describe_order(t.order) << "; want: stopped, order [4,1,3,2,0]");
  REQUIRE(t.status == sdk::PlanStatus::stopped);
  REQUIRE(t.order == std::vector<std::size_t>{4, 1, 3, 2, 0});
}

inline void check_planner_basics(const sdk::Planner& planner) {
  const auto g = split_map();
  const sdk::Cell start{1, 1, 0};
  // A path to the own cell is empty.
  {
    const sdk::Area self{start};
    const sdk::PathResult r = planner.plan(*g, {start, &self, nullptr}, sdk::StopCondition{});
    INFO("asked: a path from [1,1] to [1,1] on the split map; answered: "
         << describe_answer(*g, r) << "; want: found [1,1] by 0 steps");
    REQUIRE(r.status == sdk::PlanStatus::found);
    REQUIRE(r.path.empty());
    REQUIRE(r.target == start);
  }
  // Infeasible: a status with a message, not an exception.
  {
    const sdk::Area right{{5, 1, 0}};
    INFO("asked: a path from [1,1] to [5,1], behind the split map's wall");
    sdk::PathResult r;
    REQUIRE_NOTHROW(r = planner.plan(*g, {start, &right, nullptr}, sdk::StopCondition{}));
    INFO("answered: " << describe_answer(*g, r) << "; want: no_path with a message");
    REQUIRE(r.status == sdk::PlanStatus::no_path);
    REQUIRE(!r.message.empty());
  }
  // Goals on walls and outside the bounds are ignored.
  {
    const sdk::Area walls{{3, 1, 0}, {40, 1, 0}};
    const sdk::PathResult r = planner.plan(*g, {start, &walls, nullptr}, sdk::StopCondition{});
    INFO("asked: a path from [1,1] to the wall [3,1] and [40,1] outside; answered: "
         << describe_answer(*g, r) << "; want: no_path");
    REQUIRE(r.status == sdk::PlanStatus::no_path);
  }
  // An empty goal set is a bad request, still not an exception.
  {
    const sdk::Area empty;
    INFO("asked: a path from [1,1] to an empty goal set");
    sdk::PathResult r;
    REQUIRE_NOTHROW(r = planner.plan(*g, {start, &empty, nullptr}, sdk::StopCondition{}));
    INFO("answered: " << describe_answer(*g, r) << "; want: invalid");
    REQUIRE(r.status == sdk::PlanStatus::invalid);
  }
  // A stop condition that is already true stops at once, for paths and tours.
  const sdk::Area far{{0, 0, 0}};
  sdk::StopCondition past;
  past.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  {
    const sdk::PathResult r = planner.plan(*g, {start, &far, nullptr}, past);
    INFO("asked: a path from [1,1] to [0,0] with a deadline already past; answered: "
         << describe_answer(*g, r) << "; want: stopped");
    REQUIRE(r.status == sdk::PlanStatus::stopped);
  }
  {
    std::atomic<bool> cancel{true};
    sdk::StopCondition cancelled;
    cancelled.cancel = &cancel;
    const sdk::PathResult r = planner.plan(*g, {start, &far, nullptr}, cancelled);
    INFO("asked: a path from [1,1] to [0,0] with the cancel flag set; answered: "
         << describe_answer(*g, r) << "; want: stopped");
    REQUIRE(r.status == sdk::PlanStatus::stopped);
  }
  {
    const std::vector<sdk::Cell> pts{{0, 0, 0}, {2, 2, 0}, {5, 0, 0}};
    const sdk::TourResult t = planner.tour(*g, start, pts, past);
    INFO("asked: a tour from [1,1] over "
         << describe_cells(pts, 2)
         << " with a deadline already past; answered: " << sdk::to_string(t.status) << ", order "
         << describe_order(t.order) << "; want: stopped, every point");
    REQUIRE(t.status == sdk::PlanStatus::stopped);
    REQUIRE(t.order.size() == pts.size());
  }
  {
    // A CPU budget already spent (docs/planners.md §2) stops as well.
    sdk::StopCondition spent;
    spent.cpu_clock = sdk::this_thread_cpu_clock();
    spent.cpu_deadline = sdk::cpu_time(spent.cpu_clock);
    REQUIRE(spent.cause() == sdk::StopCause::cpu_budget);
    const sdk::PathResult r = planner.plan(*g, {start, &far, nullptr}, spent);
    INFO("asked: a path from [1,1] to [0,0] with a CPU budget already spent; answered: "
         << describe_answer(*g, r) << "; want: stopped");
    REQUIRE(r.status == sdk::PlanStatus::stopped);
  }
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

/// `requests` random path requests (a start and two goals, free cells) and `points` random tour
/// points on `g`, drawn in that order from `seed`: the same set for the same seed.
struct RandomAsks {
  std::vector<std::pair<sdk::Cell, sdk::Area>> paths;
  std::vector<sdk::Cell> points;
};
inline RandomAsks random_asks(const sdk::Geometry& g, std::uint32_t seed, int requests,
                              int points) {
  std::mt19937 rng(seed);
  const sdk::Area& free = g.free_cells();
  std::uniform_int_distribution<std::size_t> pick_free(0, free.size() - 1);
  RandomAsks out;
  for (int k = 0; k < requests; ++k) {
    sdk::Area goals{free[pick_free(rng)], free[pick_free(rng)]};
    sdk::areas::normalize(goals);
    out.paths.push_back({free[pick_free(rng)], std::move(goals)});
  }
  for (int k = 0; k < points; ++k) out.points.push_back(free[pick_free(rng)]);
  return out;
}

/// Deterministic planners answer a request the same whatever they were asked before: `factory`
/// makes a second instance that answers the same requests (and tours) in reverse order.
inline void check_history_independence(const PlannerFactory& factory, const sdk::Geometry& g,
                                       std::uint32_t seed, int requests) {
  const auto first = factory();
  if (!first->traits().deterministic) return;
  const auto second = factory();
  const sdk::Area& free = g.free_cells();
  const RandomAsks asks = random_asks(g, seed, requests, 12);
  const auto& asked = asks.paths;
  const auto& points = asks.points;
  std::vector<sdk::PathResult> forward;
  for (const auto& [start, goals] : asked)
    forward.push_back(first->plan(g, {start, &goals, nullptr}, sdk::StopCondition{}));
  const sdk::TourResult tour_after = first->tour(g, free.front(), points, sdk::StopCondition{});
  const sdk::TourResult tour_before = second->tour(g, free.front(), points, sdk::StopCondition{});
  INFO("asked: a tour from " << sdk::to_string(free.front(), g.dims()) << " over "
                             << describe_cells(points, g.dims(), 12) << " of a fresh instance "
                             << "first, and after " << asked.size() << " paths: orders "
                             << describe_order(tour_before.order) << " and "
                             << describe_order(tour_after.order));
  REQUIRE(tour_before.order == tour_after.order);
  for (std::size_t k = asked.size(); k-- > 0;) {
    INFO("request " << k << " asked last of " << asked.size() << ", then first");
    const auto& [start, goals] = asked[k];
    const sdk::PathRequest req{start, &goals, nullptr};
    const sdk::PathResult r = second->plan(g, req, sdk::StopCondition{});
    INFO("asked: a path " << describe_request(g, req)
                          << "; answered first: " << describe_answer(g, r)
                          << "; answered last: " << describe_answer(g, forward[k]));
    REQUIRE(r.status == forward[k].status);
    REQUIRE(r.path == forward[k].path);
    if (r.status == sdk::PlanStatus::found) REQUIRE(r.target == forward[k].target);
  }
}

/// The threading rule (flipper/sdk/plugin.hpp: one request at a time per instance, instances
/// concurrently): two instances answer the same paths and a tour at once, each on a thread of its
/// own, started together; each must answer as a third instance answers alone (deterministic
/// planners: the same status, path and order; others: a valid path when one is found, a
/// permutation). A plugin whose instances share unguarded state (a static buffer, a global
/// generator) fails here.
inline void check_concurrent_instances(const PlannerFactory& factory, const sdk::Geometry& g,
                                       std::uint32_t seed, int requests) {
  const auto alone = factory();
  const auto first = factory();
  const auto second = factory();
  const sdk::Area& free = g.free_cells();
  // A sampling planner gets fewer requests and tour points: each of its plans may spend its whole
  // iteration budget (a walled-off goal), and with 40 requests and 10 points this check cost
  // `ompl rrtstar` 170 s of CPU, the rest of the kit 6 s. Three rounds still overlap the threads.
  const bool sampling = alone->traits().sampling;
  const RandomAsks asks = random_asks(g, seed, sampling ? 8 : requests, sampling ? 4 : 10);
  const auto& asked = asks.paths;
  const auto& points = asks.points;
  struct Answers {
    std::vector<sdk::PathResult> paths;
    sdk::TourResult tour;
    std::string error;  // what a call threw (Catch2's checks are not for other threads)
  };
  auto answer = [&](const sdk::Planner& planner, Answers& out) {
    try {
      for (int round = 0; round < 3; ++round) {  // long enough for the two threads to overlap
        for (const auto& [start, goals] : asked)
          out.paths.push_back(planner.plan(g, {start, &goals, nullptr}, sdk::StopCondition{}));
        out.tour = planner.tour(g, free.front(), points, sdk::StopCondition{});
      }
    } catch (const std::exception& e) {
      out.error = e.what();
    }
  };
  Answers reference;
  answer(*alone, reference);
  REQUIRE(reference.error.empty());
  Answers a;
  Answers b;
  std::latch start(2);
  auto run = [&](const sdk::Planner& planner, Answers& out) {
    start.arrive_and_wait();
    answer(planner, out);
  };
  std::thread ta(run, std::cref(*first), std::ref(a));
  std::thread tb(run, std::cref(*second), std::ref(b));
  ta.join();
  tb.join();
  const bool deterministic = alone->traits().deterministic;
  for (const Answers* got : {&a, &b}) {
    const char* which = got == &a ? "the first" : "the second";
    INFO(which << " of two instances planning at once on two threads");
    REQUIRE(got->error.empty());
    REQUIRE(got->paths.size() == reference.paths.size());
    for (std::size_t k = 0; k < got->paths.size(); ++k) {
      const auto& [from, goals] = asked[k % asked.size()];
      const sdk::PathRequest req{from, &goals, nullptr};
      const sdk::PathResult& r = got->paths[k];
      INFO("request " << k << ": a path " << describe_request(g, req) << "; answered "
                      << describe_answer(g, r)
                      << "; alone: " << describe_answer(g, reference.paths[k]));
      if (r.status == sdk::PlanStatus::found) check_path_shape(g, req, r);
      if (!deterministic) continue;
      REQUIRE(r.status == reference.paths[k].status);
      REQUIRE(r.path == reference.paths[k].path);
    }
    INFO("the tour over " << describe_cells(points, g.dims(), 10) << ": order "
                          << describe_order(got->tour.order) << ", alone "
                          << describe_order(reference.tour.order));
    std::vector<std::size_t> sorted = got->tour.order;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::size_t> identity(points.size());
    std::iota(identity.begin(), identity.end(), std::size_t{0});
    REQUIRE(sorted == identity);
    if (deterministic) REQUIRE(got->tour.order == reference.tour.order);
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
    check_concurrent_instances(factory, *random_maze(2, 160, 120, 1, 0.3, 5), 5, 40);
  }
  if (traits.supports_3d) {
    check_goal_ties(*planner, 3);
    const auto g = random_maze(3, 9, 8, 7, 0.35, 11);
    check_random_requests(*planner, *g, 11, 60);
    check_tour(*planner, *g, 11);
    check_history_independence(factory, *g, 12, 20);
    if (!traits.supports_2d) check_concurrent_instances(factory, *g, 13, 40);
  }
}

}  // namespace flipper::testing

/// Defines a Catch2 test case running every planner check on the plugin from `factory`.
#define FLIPPER_PLANNER_CONFORMANCE(name, factory)                    \
  TEST_CASE(name ": planner conformance", "[conformance][planner]") { \
    ::flipper::testing::check_planner_conformance(factory);           \
  }
