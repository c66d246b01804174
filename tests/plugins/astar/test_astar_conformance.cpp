#include <catch2/catch.hpp>

#include "astar_support.hpp"
#include "flipper/testing/planner_conformance.hpp"

using namespace flipper;

FLIPPER_PLANNER_CONFORMANCE("astar", [] { return testsupport::astar(); })

FLIPPER_PLANNER_CONFORMANCE("astar without tour improvement", [] {
  return testsupport::astar(sdk::Params({{"two_opt", false}, {"or_opt", false}}));
})

FLIPPER_PLANNER_CONFORMANCE("astar with the manhattan heuristic", [] {
  return testsupport::astar(sdk::Params({{"heuristic", std::string("manhattan")}}));
})
