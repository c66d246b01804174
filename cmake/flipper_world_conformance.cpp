// The world kit (flipper/testing/world_conformance.hpp) on the plugin under test: the world of
// WORLD <file>, or a small world in the protocol's common format (bounds, robot holding an item,
// items, rooms) of the plugin's dimensions; malformed worlds: the kit's generic ones.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "flipper/testing/world_conformance.hpp"
#include "flipper_conformance_driver.hpp"

namespace {

std::string common_world(int dims) {
  if (dims == 3)
    return R"({"bounds": {"min": [0, 0, 0], "max": [5, 4, 2]},
 "robot": {"x": 1, "y": 1, "z": 0, "holding": [{"color": "blue", "shape": "square"}]},
 "items": [{"x": 3, "y": 2, "z": 0, "color": "red", "shape": "circle"},
           {"x": 3, "y": 2, "z": 0, "color": "green", "shape": "triangle"},
           {"x": 5, "y": 4, "z": 2, "color": "yellow", "shape": "square"}],
 "rooms": {"room1": [[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0]],
           "room2": [[4, 3, 2], [4, 4, 2], [5, 3, 2], [5, 4, 2]]}})";
  return R"({"bounds": {"min": [0, 0], "max": [5, 4]},
 "robot": {"x": 1, "y": 1, "holding": [{"color": "blue", "shape": "square"}]},
 "items": [{"x": 3, "y": 2, "color": "red", "shape": "circle"},
           {"x": 3, "y": 2, "color": "green", "shape": "triangle"},
           {"x": 5, "y": 4, "color": "yellow", "shape": "square"}],
 "rooms": {"room1": [[0, 0], [0, 1], [1, 0], [1, 1]], "room2": [[4, 3], [4, 4], [5, 3], [5, 4]]}})";
}

std::string good_world() {
  const std::string file = FLIPPER_CONFORMANCE_WORLD;
  if (file.empty())
    return common_world(flipper::testing::driver::plugin<flipper::sdk::World>()->dims());
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read the conformance WORLD " + file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

FLIPPER_WORLD_CONFORMANCE(FLIPPER_CONFORMANCE_PLUGIN,
                          [] { return flipper::testing::driver::plugin<flipper::sdk::World>(); },
                          good_world(), {})
