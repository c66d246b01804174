// The rewriter kit (flipper/testing/rewriter_conformance.hpp) on the plugin under test: bodies of
// moves, picks and a repeated block on a small free grid, without an execution service (a
// rewriter must then still answer, possibly with less).
#include <catch2/catch.hpp>

#include "flipper/sdk/canonical.hpp"
#include "flipper/testing/rewriter_conformance.hpp"
#include "flipper_conformance_driver.hpp"

namespace {

flipper::sdk::WorldState small_world() {
  using namespace flipper::sdk;
  WorldState w;
  w.geometry = std::make_shared<const Geometry>(
      2, Cell{0, 0, 0}, Cell{5, 4, 0}, std::vector<std::uint8_t>(30, 1),
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, Cell>>{
          {"right", {1, 0, 0}}, {"left", {-1, 0, 0}}, {"up", {0, 1, 0}}, {"down", {0, -1, 0}}});
  w.rooms = std::make_shared<const RoomMap>(RoomMap{{"room1", {{0, 0, 0}, {1, 0, 0}}}});
  w.robot = {1, 1, 0};
  w.items = {{{0, "red", "circle"}, {3, 2, 0}}, {{1, "blue", "square"}, {3, 2, 0}}};
  w.next_item_id = 2;
  return w;
}

}  // namespace

TEST_CASE(FLIPPER_CONFORMANCE_PLUGIN ": rewriter conformance", "[conformance][rewriter]") {
  using namespace flipper;
  const auto rewriter = testing::driver::plugin<sdk::Rewriter>();
  for (const char* body :
       {"{move right}", "{{move up};{move up};{move left}}", "{{pick item };{pick item }}",
        "{{drop item};{drop item}}", "{visit room1}"}) {
    INFO("body: " << body);
    testing::check_rewriter_conformance(
        *rewriter, {sdk::read_canonical(body), small_world(), nullptr, sdk::tokenize("do it")});
  }
}
