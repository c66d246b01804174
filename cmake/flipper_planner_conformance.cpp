// The planner kit (flipper/testing/planner_conformance.hpp) on the plugin under test.
#include <catch2/catch.hpp>

#include "flipper/testing/planner_conformance.hpp"
#include "flipper_conformance_driver.hpp"

FLIPPER_PLANNER_CONFORMANCE(FLIPPER_CONFORMANCE_PLUGIN, [] {
  return flipper::testing::driver::plugin<flipper::sdk::Planner>();
})
