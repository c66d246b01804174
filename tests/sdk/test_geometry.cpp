#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"

using namespace flipper::sdk;

TEST_CASE("area set operations keep (x, y, z) order", "[geometry]") {
  Area a{{2, 1, 0}, {0, 0, 0}, {1, 5, 0}, {0, 0, 0}};
  areas::normalize(a);
  REQUIRE(a == Area{{0, 0, 0}, {1, 5, 0}, {2, 1, 0}});
  Area b{{1, 5, 0}, {3, 3, 0}};
  REQUIRE(areas::unite(a, b) == Area{{0, 0, 0}, {1, 5, 0}, {2, 1, 0}, {3, 3, 0}});
  REQUIRE(areas::intersect(a, b) == Area{{1, 5, 0}});
  REQUIRE(areas::subtract(a, b) == Area{{0, 0, 0}, {2, 1, 0}});
  REQUIRE(areas::contains(a, {2, 1, 0}));
  REQUIRE(!areas::contains(a, {2, 2, 0}));
}

TEST_CASE("geometry indexes cells and lists free ones sorted", "[geometry]") {
  // 3 x 2 box from (-1,-1): free everywhere except (0,-1).
  std::vector<std::uint8_t> mask(6, 1);
  Geometry g(2, {-1, -1, 0}, {1, 0, 0}, mask, {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
             {{"right", {1, 0, 0}}, {"up", {0, 1, 0}}});
  REQUIRE(g.cell_count() == 6);
  for (std::size_t i = 0; i < g.cell_count(); ++i) REQUIRE(g.index(g.cell_at(i)) == i);
  REQUIRE(g.is_free({1, 0, 0}));
  REQUIRE(!g.is_free({2, 0, 0}));
  REQUIRE(g.direction("up") == Cell{0, 1, 0});
  REQUIRE(!g.direction("north"));
  REQUIRE(g.free_cells().size() == 6);
  REQUIRE(std::is_sorted(g.free_cells().begin(), g.free_cells().end()));
  REQUIRE_THROWS_AS(Geometry(2, {0, 0, 0}, {1, 1, 0}, std::vector<std::uint8_t>(3, 1), {}, {}),
                    Error);
}
