#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/testing/planner_conformance.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

std::shared_ptr<sdk::Planner> ompl(const sdk::Params& p = {}) {
  return testsupport::load_plugin<sdk::Planner>("ompl", p);
}

// Every step is a neighbour step into a free, non-avoided cell, and (3-D) the body can make it.
void check_snapped(const sdk::Geometry& g, const sdk::PathRequest& req, const sdk::PathResult& r) {
  testing::check_path_shape(g, req, r);
  if (const sdk::ContinuousSpace* space = g.continuous()) {
    Cell at = req.start;
    for (const Cell& c : r.path) {
      const double a[3] = {double(at.x), double(at.y), double(at.z)};
      const double b[3] = {double(c.x), double(c.y), double(c.z)};
      REQUIRE(space->is_state_valid(b));
      REQUIRE(space->is_motion_valid(a, b));
      at = c;
    }
  }
}

// 2-D mask: a 12 x 9 box with a wall x = 6 (y 0..7) open only at the top row y = 8.
std::shared_ptr<const sdk::Geometry> u_turn() {
  std::vector<std::uint8_t> mask(12 * 9, 1);
  for (int y = 0; y <= 7; ++y) mask[static_cast<std::size_t>(6 + 12 * y)] = 0;
  return std::make_shared<const sdk::Geometry>(
      2, Cell{0, 0, 0}, Cell{11, 8, 0}, std::move(mask),
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, Cell>>{});
}

}  // namespace

TEST_CASE("ompl: 3-D path between floors is snapped, connected and collision-free", "[ompl]") {
  const sdk::WorldState s = testsupport::two_floors();
  auto planner = ompl();
  const sdk::PathRequest req{s.robot, &s.rooms->at("room4"), nullptr};
  const sdk::PathResult r = planner->plan(*s.geometry, req, sdk::StopCondition{});
  INFO(r.message);
  check_snapped(*s.geometry, req, r);
  // The goal is the nearest room4 cell by straight line: (1,5,2), sqrt(20) away.
  REQUIRE(r.target == Cell{1, 5, 2});
  REQUIRE(r.path.size() >= 23);  // never shorter than the BFS optimum
  REQUIRE(std::find(r.path.begin(), r.path.end(), Cell{8, 1, 1}) != r.path.end());
  REQUIRE(r.expansions > 0);
}

TEST_CASE("ompl: the avoid set is an obstacle, the start is exempt", "[ompl]") {
  const auto g = u_turn();
  auto planner = ompl();
  // Avoid row y = 7 left of the wall except at x = 5: the way up to the opening (6,8) is the
  // one lane (5,7).
  sdk::Area avoid;
  for (int x = 0; x <= 4; ++x) avoid.push_back({x, 7, 0});
  sdk::areas::normalize(avoid);
  const sdk::Area goal{{9, 1, 0}};
  const sdk::PathRequest req{{1, 1, 0}, &goal, &avoid};
  const sdk::PathResult r = planner->plan(*g, req, sdk::StopCondition{});
  check_snapped(*g, req, r);
  REQUIRE(r.path.size() >= 22);  // around the wall: up to y = 8 and back down
  REQUIRE(std::find(r.path.begin(), r.path.end(), Cell{5, 7, 0}) != r.path.end());
  // Start inside the avoid set: still allowed to leave it.
  const sdk::PathRequest from_inside{{2, 7, 0}, &goal, &avoid};
  const sdk::PathResult left = planner->plan(*g, from_inside, sdk::StopCondition{});
  check_snapped(*g, from_inside, left);
  // Blocking the only opening makes it infeasible: a status, at once, with a message.
  sdk::Area gate{{6, 8, 0}};
  const sdk::PathResult none = planner->plan(*g, {{1, 1, 0}, &goal, &gate}, sdk::StopCondition{});
  REQUIRE(none.status == sdk::PlanStatus::no_path);
  REQUIRE(none.message.find("reachable") != std::string::npos);
}

TEST_CASE("ompl: on the 3-D world, avoiding room2 leaves floor 1 unreachable", "[ompl]") {
  const sdk::WorldState s = testsupport::two_floors();
  const sdk::PathResult r = ompl()->plan(
      *s.geometry, {s.robot, &s.rooms->at("room4"), &s.rooms->at("room2")}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::no_path);
  REQUIRE(!r.message.empty());
}

TEST_CASE("ompl: a goal inside the avoid set is not a goal unless it is the start", "[ompl]") {
  const auto g = u_turn();
  const sdk::Area goal{{2, 2, 0}};
  sdk::PathResult r = ompl()->plan(*g, {{1, 1, 0}, &goal, &goal}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::no_path);
  REQUIRE(r.message.find("avoid") != std::string::npos);
  const sdk::Area self{{1, 1, 0}};
  r = ompl()->plan(*g, {{1, 1, 0}, &self, &self}, sdk::StopCondition{});
  REQUIRE(r.status == sdk::PlanStatus::found);
  REQUIRE(r.path.empty());
}

TEST_CASE("ompl: the same seed gives the same path, and every planner is deterministic", "[ompl]") {
  const sdk::WorldState s = testsupport::two_floors();
  const sdk::PathRequest req{s.robot, &s.rooms->at("room4"), nullptr};
  for (const char* name : {"rrtconnect", "rrt", "rrtstar", "prm"}) {
    INFO(name);
    const sdk::Params p({{"planner", std::string(name)}, {"seed", std::int64_t{7}}});
    auto a = ompl(p);
    auto b = ompl(p);
    REQUIRE(a->traits().deterministic);
    const auto ra = a->plan(*s.geometry, req, sdk::StopCondition{});
    const auto rb = b->plan(*s.geometry, req, sdk::StopCondition{});
    INFO(ra.message);
    REQUIRE(ra.status == sdk::PlanStatus::found);
    REQUIRE(ra.path == rb.path);
    REQUIRE(ra.expansions == rb.expansions);
    REQUIRE(a->plan(*s.geometry, req, sdk::StopCondition{}).path == ra.path);
    // Another seed samples otherwise: the work differs (the seed is used at all).
    auto c = ompl(sdk::Params({{"planner", std::string(name)}, {"seed", std::int64_t{8}}}));
    REQUIRE(c->plan(*s.geometry, req, sdk::StopCondition{}).expansions != ra.expansions);
  }
  const auto t = ompl()->traits();
  REQUIRE(t.supports_2d);
  REQUIRE(t.supports_3d);
  REQUIRE_FALSE(t.optimal);
  REQUIRE(t.sampling);
}

TEST_CASE("ompl: max_iterations is the budget, exactly: N checks find what N - 1 cannot",
          "[ompl]") {
  // The checks a request used (PathResult::expansions) are the budget's unit: with exactly that
  // many the same path is found again, with one fewer the request is no_path naming the budget.
  const sdk::WorldState floors = testsupport::two_floors();
  const auto g2 = u_turn();
  const sdk::Area room4 = floors.rooms->at("room4"), across{{9, 1, 0}};
  struct Case {
    const sdk::Geometry* g;
    sdk::PathRequest req;
  };
  const std::vector<Case> cases = {{floors.geometry.get(), {floors.robot, &room4, nullptr}},
                                   {g2.get(), {{1, 1, 0}, &across, nullptr}}};
  for (const char* name : {"rrtconnect", "rrt"})
    for (const Case& k : cases) {
      INFO(name << " on a " << k.g->dims() << "-D world");
      const sdk::PathResult full =
          ompl(sdk::Params({{"planner", std::string(name)}}))->plan(*k.g, k.req, {});
      REQUIRE(full.status == sdk::PlanStatus::found);
      const auto n = static_cast<std::int64_t>(full.expansions);
      REQUIRE(n > 1);
      const sdk::PathResult exact =
          ompl(sdk::Params({{"planner", std::string(name)}, {"max_iterations", n}}))
              ->plan(*k.g, k.req, {});
      REQUIRE(exact.status == sdk::PlanStatus::found);
      REQUIRE(exact.path == full.path);
      const sdk::PathResult short_by_one =
          ompl(sdk::Params({{"planner", std::string(name)}, {"max_iterations", n - 1}}))
              ->plan(*k.g, k.req, {});
      REQUIRE(short_by_one.status == sdk::PlanStatus::no_path);
      REQUIRE(short_by_one.message == std::string("no path found by ") + name +
                                          " within max_iterations = " + std::to_string(n - 1) +
                                          " to " + sdk::to_string(full.target, k.g->dims()));
    }
}

TEST_CASE("ompl: a time budget, seed 0 and a bad budget are bad_config with the reason", "[ompl]") {
  auto refused = [](const sdk::Params& p) -> std::string {
    try {
      (void)ompl(p);
    } catch (const sdk::Error& e) {
      REQUIRE(e.code() == sdk::codes::kBadConfig);
      return e.what();
    }
    FAIL("accepted");
    return {};
  };
  const std::string budget = refused(sdk::Params({{"time_budget_ms", std::int64_t{500}}}));
  CHECK(budget ==
        "ompl: time_budget_ms is retired: it was a wall-clock budget per path request, so the plan "
        "depended on the machine's load; the budget counts work now: max_iterations (termination "
        "checks per path request, default 100000; docs/planners.md §3)");
  // Through the kernel's validation the same reason is a bad_config naming the full key.
  sdk::ParamSchema schema;
  schema.add_int("max_iterations", 1, "").add_retired("time_budget_ms", "use max_iterations");
  try {
    (void)sdk::validate_params(schema, {{"time_budget_ms", std::string("500")}}, "planner.params");
    FAIL("accepted");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kBadConfig);
    CHECK(std::string(e.what()) ==
          "config key 'planner.params.time_budget_ms' is retired: use max_iterations");
  }
  // Seed 0 (unseeded) and a budget of 0 are refused by the params' ranges, also for a host that
  // did not validate; the seed's description says why 0 is not offered.
  CHECK(refused(sdk::Params({{"seed", std::int64_t{0}}})) ==
        "param 'seed' = 0 is out of range [1, 4294967295]");
  CHECK(refused(sdk::Params({{"seed", std::int64_t{4294967296}}})) ==
        "param 'seed' = 4294967296 is out of range [1, 4294967295]");
  CHECK(refused(sdk::Params({{"max_iterations", std::int64_t{0}}})) ==
        "param 'max_iterations' = 0 is out of range [1, 100000000]");
  CHECK(refused(sdk::Params({{"max_iterations", std::int64_t{100000001}}})) ==
        "param 'max_iterations' = 100000001 is out of range [1, 100000000]");
  const sdk::ParamSchema declared =
      testing::PluginLibrary(testing::plugin_path("ompl", FLIPPER_PLUGIN_DIR)).schema();
  REQUIRE(declared.find("seed") != nullptr);
  CHECK_THAT(declared.find("seed")->description, Catch::Contains("unseeded"));
  // 1 is the smallest budget; it plans (and finds nothing to a far goal).
  const sdk::WorldState s = testsupport::two_floors();
  const auto one = ompl(sdk::Params({{"max_iterations", std::int64_t{1}}}))
                       ->plan(*s.geometry, {s.robot, &s.rooms->at("room4"), nullptr}, {});
  CHECK(one.status == sdk::PlanStatus::no_path);
}

TEST_CASE("ompl: an expansion budget of one stops the planner", "[ompl]") {
  const sdk::WorldState s = testsupport::two_floors();
  sdk::StopCondition stop;
  stop.max_expansions = 1;
  const auto r = ompl()->plan(*s.geometry, {s.robot, &s.rooms->at("room4"), nullptr}, stop);
  REQUIRE(r.status == sdk::PlanStatus::stopped);
  REQUIRE(!r.message.empty());
}

TEST_CASE("ompl: study world (grid2d), core-language example 6", "[ompl][grid2d]") {
  auto world = testsupport::load_plugin<sdk::World>("grid2d");
  const sdk::WorldState s =
      world->load(testsupport::read_text(testsupport::worlds_dir() + "/study2018.json"),
                  testsupport::worlds_dir());
  auto planner = ompl();
  const sdk::Area target{{9, 8, 0}};
  const sdk::Area& room3 = s.rooms->at("room3");
  // From (2,4), inside room3, every neighbour is in room3: infeasible.
  REQUIRE(planner->plan(*s.geometry, {{2, 4, 0}, &target, &room3}, sdk::StopCondition{}).status ==
          sdk::PlanStatus::no_path);
  // From (7,7) it works without touching room3.
  const sdk::PathRequest req{{7, 7, 0}, &target, &room3};
  check_snapped(*s.geometry, req, planner->plan(*s.geometry, req, sdk::StopCondition{}));
  // Without avoid set, anywhere to anywhere free on the map.
  testing::check_random_requests(*planner, *s.geometry, 5, 40);
}

TEST_CASE("ompl: bad parameters are bad_config", "[ompl]") {
  try {
    (void)ompl(sdk::Params({{"planner", std::string("astar")}}));
    FAIL("accepted");
  } catch (const sdk::Error& e) {
    REQUIRE(e.code() == sdk::codes::kBadConfig);
    REQUIRE(std::string(e.what()).find("astar") != std::string::npos);
  }
}
