// The planner kit's random requests (flipper/testing/planner_conformance.hpp) on evil_planner in
// mode `wall`: the kit must fail, and its message must name the scenario — the request, the
// answer and what is wrong with it (docs/plugins-untrusted.md §5). Registered as
// kits.failure_names_the_scenario, which passes when the output says all that. (The whole kit
// stops earlier on this planner: its breadth-first search does not keep the tie rule.)
#include <catch2/catch.hpp>

#include "flipper/testing/planner_conformance.hpp"
#include "flipper_conformance_driver.hpp"

TEST_CASE("the planner kit's random requests on a planner that walks through walls") {
  const auto planner = flipper::testing::driver::plugin<flipper::sdk::Planner>();
  const auto maze = flipper::testing::random_maze(2, 24, 17, 1, 0.3, 1);
  flipper::testing::check_random_requests(*planner, *maze, 1, 60);
}
