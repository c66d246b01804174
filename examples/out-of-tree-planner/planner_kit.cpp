// The planner behaviour kit on the built plugin, loaded as the kernel loads it: paths, ties among
// equally near goals, stop conditions, determinism, tours
// (flipper/testing/planner_conformance.hpp).
#include <catch2/catch.hpp>

#include <flipper/testing/loader.hpp>
#include <flipper/testing/planner_conformance.hpp>

FLIPPER_PLANNER_CONFORMANCE("bfs_example", [] {
  return flipper::testing::load_library_plugin<flipper::sdk::Planner>(
      FLIPPER_CONFORMANCE_PLUGIN_PATH);
})
