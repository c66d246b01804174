// bfs_example's own tests, beside the conformance kits: the plugin created as the kernel creates
// it (testing::load_plugin validates its parameters against its schema), on a corridor of 10
// cells whose shortest path is known.
#include <catch2/catch.hpp>
#include <flipper/sdk/errors.hpp>
#include <flipper/sdk/planner.hpp>
#include <flipper/testing/plugin_factory.hpp>

namespace {

using flipper::sdk::Cell;

const auto kCorridor = std::make_shared<const flipper::sdk::Geometry>(
    2, Cell{0, 0, 0}, Cell{9, 0, 0}, std::vector<std::uint8_t>(10, 1),
    std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}},
    std::vector<std::pair<std::string, Cell>>{{"right", {1, 0, 0}}, {"left", {-1, 0, 0}}});

flipper::sdk::PathResult end_to_end(const flipper::sdk::Planner& planner) {
  const flipper::sdk::Area goal{{9, 0, 0}};
  return planner.plan(*kCorridor, {{0, 0, 0}, &goal, nullptr}, {});
}

}  // namespace

TEST_CASE("bfs_example: the corridor's 9 steps, or stopped by max_expansions") {
  using flipper::testing::load_plugin;
  const auto unlimited = load_plugin<flipper::sdk::Planner>("bfs_example");
  const auto r = end_to_end(*unlimited);
  REQUIRE(r.status == flipper::sdk::PlanStatus::found);
  CHECK(r.path.size() == 9);
  CHECK(r.expansions == 9);  // cells 0..8 expanded before 9 is reached
  // 9 expansions are enough, 8 are not.
  CHECK(end_to_end(*load_plugin<flipper::sdk::Planner>("bfs_example", {{"max_expansions", 9}}))
            .status == flipper::sdk::PlanStatus::found);
  CHECK(end_to_end(*load_plugin<flipper::sdk::Planner>("bfs_example", {{"max_expansions", 8}}))
            .status == flipper::sdk::PlanStatus::stopped);
  // The schema refuses what the kernel would refuse.
  CHECK_THROWS_AS(load_plugin<flipper::sdk::Planner>("bfs_example", {{"max_expansions", -1}}),
                  flipper::sdk::Error);
}
