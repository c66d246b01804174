#include <catch2/catch.hpp>
#include <limits>

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

TEST_CASE("geometry refuses bounds whose cell count does not fit, instead of wrapping to zero",
          "[geometry]") {
  constexpr int lo = std::numeric_limits<int>::min();
  constexpr int hi = std::numeric_limits<int>::max();
  // 2^32 x 2^32 cells: the product wraps to 0 in 64 bits, which an empty mask would "match".
  REQUIRE_THROWS_AS(Geometry(2, {lo, lo, 0}, {hi, hi, 0}, {}, {}, {}), Error);
  // One row spanning the whole int range: 2^32 cells, which no mask here has (int arithmetic
  // would wrap the extent itself to 0).
  REQUIRE_THROWS_AS(Geometry(2, {lo, 0, 0}, {hi, 0, 0}, {}, {}, {}), Error);
  // The boundary that fits: a 1 x 1 box at the extremes is one cell.
  const Geometry corner(2, {hi, lo, 0}, {hi, lo, 0}, std::vector<std::uint8_t>(1, 1), {}, {});
  REQUIRE(corner.cell_count() == 1);
  REQUIRE(corner.is_free({hi, lo, 0}));
}
