// One set of programs, four world x planner pairs. Expectations depend on the world (the maps
// differ) but never on the planner: swapping astar for ompl changes paths, not effects.
#include <catch2/catch.hpp>
#include <deque>
#include <map>

#include "flipper/kernel/executor.hpp"
#include "flipper/sdk/canonical.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

struct Pair {
  std::string world;    // grid2d | octomap3d
  std::string planner;  // astar | ompl
};

sdk::WorldState start_world(const std::string& kind) {
  if (kind == "grid2d")
    return testsupport::load_plugin<sdk::World>("grid2d")->load(
        testsupport::read_text(testsupport::worlds_dir() + "/study2018.json"),
        testsupport::worlds_dir());
  return testsupport::two_floors();
}

sdk::Outcome run(const Pair& p, const std::string& canonical, const sdk::WorldState& s) {
  auto planner = testsupport::load_plugin<sdk::Planner>(p.planner);
  const kernel::Executor exec(planner);
  return exec.run(sdk::read_canonical(canonical), s);
}

bool in_room(const sdk::WorldState& s, const std::string& room) {
  return sdk::areas::contains(s.rooms->at(room), s.robot);
}

std::size_t lying_in(const sdk::WorldState& s, const std::string& room, const std::string& color) {
  std::size_t n = 0;
  for (const auto& li : s.items)
    if (li.item.color == color && sdk::areas::contains(s.rooms->at(room), li.at)) ++n;
  return n;
}

// The trace is a walk of neighbour steps through free cells from the start.
void check_trace(const sdk::WorldState& start, const sdk::Outcome& o) {
  const sdk::Geometry& g = *start.geometry;
  Cell at = start.robot;
  for (const auto& step : o.trace) {
    if (step.act != sdk::TraceStep::Act::move) {
      REQUIRE(step.cell == at);
      continue;
    }
    const Cell d{step.cell.x - at.x, step.cell.y - at.y, step.cell.z - at.z};
    const auto& offs = g.neighbour_offsets();
    REQUIRE(std::find(offs.begin(), offs.end(), d) != offs.end());
    REQUIRE(g.is_free(step.cell));
    at = step.cell;
  }
  REQUIRE(at == o.world.robot);
}

/// Independent oracle for `visit` of several goal cells (core-language §4.4, §8): breadth-first
/// path distances over the free cells and the world's neighbours; the nearest goal, ties by the
/// smallest (x, y, z). Returns the start when no goal is reachable.
Cell nearest_by_path(const sdk::WorldState& s, const std::vector<Cell>& goals) {
  const sdk::Geometry& g = *s.geometry;
  std::map<Cell, int> dist{{s.robot, 0}};
  std::deque<Cell> todo{s.robot};
  while (!todo.empty()) {
    const Cell c = todo.front();
    todo.pop_front();
    for (const Cell& d : g.neighbour_offsets()) {
      const Cell n = c + d;
      if (g.is_free(n) && dist.emplace(n, dist[c] + 1).second) todo.push_back(n);
    }
  }
  Cell best = s.robot;
  int best_d = -1;
  for (const Cell& goal : goals) {
    auto it = dist.find(goal);
    if (it == dist.end()) continue;
    if (best_d < 0 || it->second < best_d || (it->second == best_d && goal < best)) {
      best = goal;
      best_d = it->second;
    }
  }
  return best;
}

std::vector<Cell> cells_with(const sdk::WorldState& s, const std::string& color) {
  std::vector<Cell> out;
  for (const auto& li : s.items)
    if (color.empty() || li.item.color == color) out.push_back(li.at);
  return out;
}

const std::vector<Pair> kPairs = {
    {"grid2d", "astar"}, {"grid2d", "ompl"}, {"octomap3d", "astar"}, {"octomap3d", "ompl"}};

}  // namespace

TEST_CASE("swap: the same programs have the same effects on all four pairs", "[swap]") {
  for (const Pair& p : kPairs) {
    const bool flat = p.world == "grid2d";
    DYNAMIC_SECTION(p.world << " x " << p.planner) {
      const sdk::WorldState s = start_world(p.world);
      const std::size_t total = s.items.size() + s.held.size();

      // visits
      sdk::Outcome o = run(p, "{visit room4}", s);
      check_trace(s, o);
      REQUIRE(o.realizable);
      REQUIRE(in_room(o.world, "room4"));
      if (!flat) {  // floor 1 is only reached through the shaft
        REQUIRE(std::any_of(o.trace.begin(), o.trace.end(), [](const auto& t) {
          return t.cell == Cell{8, 1, 1};
        }));
      }

      // visit + pick
      o = run(p, "{{visit {world containing item {is red}}};{pick item {is red}}}", s);
      check_trace(s, o);
      REQUIRE(o.realizable);
      REQUIRE(o.world.held.size() == 1);
      REQUIRE(o.world.held[0].color == "red");

      // avoid: the study map reaches room4 without room2; the two-floor world cannot (the
      // shaft is in room2), and the robot stays put.
      o = run(p, "{visit room4 while avoiding room2}", s);
      check_trace(s, o);
      REQUIRE(o.realizable == flat);
      if (flat) {
        REQUIRE(in_room(o.world, "room4"));
        for (const auto& t : o.trace) REQUIRE(!sdk::areas::contains(s.rooms->at("room2"), t.cell));
      } else {
        REQUIRE(o.world.robot == s.robot);
        REQUIRE(o.warnings.size() == 1);
      }

      // foreach point + pick every: everything is collected
      o = run(p, "{foreach point in {world containing item } {{visit point};{pick every item }}}",
              s);
      check_trace(s, o);
      REQUIRE(o.realizable);
      REQUIRE(o.world.items.empty());
      REQUIRE(o.world.held.size() == total);

      // pick / drop: one blue item more lies in room1, nothing is held
      o = run(p,
              "{{visit {world containing item {is blue}}};{pick item {is blue}};{visit room1};"
              "{drop every item }}",
              s);
      check_trace(s, o);
      REQUIRE(o.realizable);
      REQUIRE(o.world.held.empty());
      REQUIRE(in_room(o.world, "room1"));
      REQUIRE(lying_in(o.world, "room1", "blue") == lying_in(s, "room1", "blue") + 1);

      // strict: no purple item anywhere, so nothing at all happens
      o = run(p, "{strict {{visit room4};{pick item {is purple}}}}", s);
      REQUIRE(!o.realizable);
      REQUIRE(o.trace.empty());
      REQUIRE(o.world.same_state(s));
      REQUIRE(!o.warnings.empty());

      // foreach area: every room is visited, once each
      o = run(p, "{foreach area in rooms {visit area}}", s);
      check_trace(s, o);
      REQUIRE(o.realizable);
      REQUIRE(!o.error);
    }
  }
}

TEST_CASE("swap: visiting one of several goals goes to the nearest by path on all four pairs",
          "[swap][defects]") {
  for (const Pair& p : kPairs) {
    DYNAMIC_SECTION(p.world << " x " << p.planner) {
      const sdk::WorldState s = start_world(p.world);
      // On the study map the red triangle at [4,0] is nearer in a straight line than the red
      // circle at [7,4], but 4 steps farther by path.
      if (p.world == "grid2d") {
        const sdk::Outcome o =
            run(p, "{{visit {world containing item {is red}}};{pick item {is red}}}", s);
        REQUIRE(o.realizable);
        CHECK(o.world.robot == Cell{7, 4, 0});
        REQUIRE(o.world.held.size() == 1);
        CHECK(o.world.held[0].shape == "circle");
      }
      for (const std::string color : {"", "red", "blue", "green", "yellow"}) {
        const std::string filter = color.empty() ? "" : "{is " + color + "}";
        const std::vector<Cell> goals = cells_with(s, color);
        if (goals.empty()) continue;
        const Cell want = nearest_by_path(s, goals);
        INFO("visit world containing item " << filter << " from " << sdk::to_string(s.robot, 3));
        const sdk::Outcome o = run(p, "{visit {world containing item " + filter + "}}", s);
        check_trace(s, o);
        REQUIRE(o.realizable);
        INFO("reached " << sdk::to_string(o.world.robot, 3) << ", nearest by path "
                        << sdk::to_string(want, 3));
        CHECK(o.world.robot == want);
        // Then the same from the goal area's far side: start at the farthest goal.
        sdk::WorldState there = s;
        there.robot = goals.back();
        const sdk::Outcome back =
            run(p,
                "{visit {{world containing item " + filter + "} minus {[" +
                    sdk::to_string(goals.back(), p.world == "grid2d" ? 2 : 3) + "]}}}",
                there);
        std::vector<Cell> others;
        for (const Cell& c : goals)
          if (c != goals.back()) others.push_back(c);
        if (others.empty()) continue;
        check_trace(there, back);
        INFO("from the farthest goal: reached " << sdk::to_string(back.world.robot, 3));
        CHECK(back.world.robot == nearest_by_path(there, others));
      }
    }
  }
}

TEST_CASE("swap: 3-D moves use the plan-view words and ascend/descend", "[swap]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto move = [](const char* dir) {
    return sdk::make(sdk::Kind::Move, {sdk::make_word(sdk::Kind::Direction, dir)});
  };
  const kernel::Executor exec(testsupport::load_plugin<sdk::Planner>("astar"));
  sdk::WorldState at_shaft = s;
  at_shaft.robot = {8, 1, 0};
  sdk::Outcome o = exec.run(move("ascend"), at_shaft);
  REQUIRE(o.realizable);
  REQUIRE(o.world.robot == Cell{8, 1, 1});
  o = exec.run(move("ascend"), s);  // the slab is above (1,1,0)
  REQUIRE(!o.realizable);
  REQUIRE(o.world.robot == s.robot);
  o = exec.run(move("up"), s);
  REQUIRE(o.world.robot == Cell{1, 2, 0});
  o = exec.run(move("left"), s);
  REQUIRE(o.world.robot == Cell{0, 1, 0});
}

TEST_CASE("swap: astar and ompl agree exactly on the edge cases the SDK decides", "[swap]") {
  // Planner::plan/tour settle an empty goal set, a start outside the bounds, a stop
  // that already fired and an empty tour before either plugin runs.
  const sdk::WorldState s = start_world("grid2d");
  const sdk::Geometry& g = *s.geometry;
  sdk::StopCondition fired;
  fired.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  const sdk::Area empty, room1 = s.rooms->at("room1");
  const std::vector<Cell> points{{11, 1, 0}, {0, 0, 0}, {9, 0, 0}};
  struct Seen {
    std::string empty_goals, fired_plan, outside, fired_tour, no_points;
  };
  std::map<std::string, Seen> seen;
  for (const char* name : {"astar", "ompl"}) {
    const auto planner = testsupport::load_plugin<sdk::Planner>(name);
    auto path = [&](const sdk::PathResult& r) {
      return std::string(sdk::to_string(r.status)) + ": " + r.message + " (" +
             std::to_string(r.path.size()) + " cells)";
    };
    auto tour = [&](const sdk::TourResult& t) {
      std::string order;
      for (std::size_t i : t.order) order += std::to_string(i) + " ";
      return std::string(sdk::to_string(t.status)) + ": " + order;
    };
    seen[name] = {path(planner->plan(g, {s.robot, &empty, nullptr}, fired)),
                  path(planner->plan(g, {s.robot, &room1, nullptr}, fired)),
                  path(planner->plan(g, {{99, 0, 0}, &room1, nullptr}, {})),
                  tour(planner->tour(g, s.robot, points, fired)),
                  tour(planner->tour(g, s.robot, {}, fired))};
  }
  for (const char* name : {"astar", "ompl"}) {
    INFO(name);
    const Seen& r = seen[name];
    CHECK(r.empty_goals == "invalid: the goal set is empty (0 cells)");
    CHECK(r.fired_plan == "stopped: stopped before planning (0 cells)");
    CHECK(r.outside == "invalid: start [99,0] is outside the bounds (0 cells)");
    CHECK(r.fired_tour == "stopped: 1 2 0 ");  // (x, y, z) order: [0,0], [9,0], [11,1]
    CHECK(r.no_points == "found: ");
  }
}

TEST_CASE("swap: an OMPL budget that runs out fails the visit, and the warning names it",
          "[swap]") {
  // max_iterations counts work (docs/planners.md §2): one check finds no way from [2,4] to [9,8]
  // on the study map, on every machine alike; the warning says it was the budget, not a wall.
  const sdk::WorldState s = start_world("grid2d");
  const kernel::Executor exec(testsupport::load_plugin<sdk::Planner>(
      "ompl", sdk::Params({{"max_iterations", std::int64_t{1}}})));
  const sdk::Outcome o = exec.run(sdk::read_canonical("{visit [9,8]}"), s);
  REQUIRE_FALSE(o.error);
  CHECK_FALSE(o.realizable);
  CHECK(o.world.robot == s.robot);
  REQUIRE(o.warnings.size() == 1);
  CHECK(o.warnings[0] ==
        "Could not complete the action: {visit [9,8]} ([9,8] is unreachable; the planner: no path "
        "found by rrtconnect within max_iterations = 1 to [9,8])");
}
