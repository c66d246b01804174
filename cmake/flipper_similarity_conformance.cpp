// The similarity kit (flipper/testing/similarity_conformance.hpp) on the plugin under test, with
// word samples of the robot domain (the kit adds empty and unknown-word ones).
#include <catch2/catch.hpp>

#include "flipper/testing/similarity_conformance.hpp"
#include "flipper_conformance_driver.hpp"

TEST_CASE(FLIPPER_CONFORMANCE_PLUGIN ": similarity conformance", "[conformance][similarity]") {
  const auto similarity = flipper::testing::driver::plugin<flipper::sdk::Similarity>();
  flipper::testing::check_similarity_conformance(*similarity,
                                                 {{"visit", "red", "triangle"},
                                                  {"go", "to", "the", "red", "triangle"},
                                                  {"pick", "every", "blue", "item"},
                                                  {"move", "up"},
                                                  {"drop", "item", "in", "room1"}});
}
