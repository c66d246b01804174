// Pixel -> occupancy value, by hand: Nav2's map_io (docs/ros-maps.md, "Cells"). The expected
// values are computed below each case from p = (255 - v) / 255 (or v / 255 with negate) in
// double arithmetic, as Nav2 computes them.
#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "map_yaml.hpp"
#include "occupancy.hpp"
#include "pgm.hpp"

using namespace flipper::plugins::ros_map;

namespace {

MapYaml yaml(MapMode mode, bool negate, double occupied, double free_thresh) {
  MapYaml m;
  m.mode = mode;
  m.negate = negate;
  m.occupied_thresh = occupied;
  m.free_thresh = free_thresh;
  m.resolution = 0.05;
  return m;
}

// 4 x 3, rows from the top of the image.
const char kImage[] =
    "P2\n4 3\n255\n"
    "0 101 102 103\n"
    "153 203 204 205\n"
    "100 254 255 50\n";

std::vector<std::int8_t> values(const MapYaml& m) {
  return occupancy_grid(decode_pgm(kImage, "tiny.pgm", 100), m).values;
}

}  // namespace

TEST_CASE("trinary at the thresholds: occupied above occupied_thresh, free below free_thresh",
          "[ros_map][values]") {
  // occupied_thresh 0.6, free_thresh 0.2. v = 101: p = 154/255 = 0.6039 > 0.6 -> 100.
  // v = 102: p = 1 - 102/255 = 0.6 (the same double as 0.6) -> not above -> unknown.
  // v = 103: p = 0.5961 -> unknown. v = 153: p = 0.4 -> unknown. v = 203: p = 0.2039 -> unknown.
  // v = 204: p = 0.2 exactly, but 1 - 0.8 is 0.19999999999999996 in doubles (Nav2's arithmetic)
  // < 0.2 -> free. v = 205: 0.196 -> free. v = 100: p = 0.6078 -> 100. v = 50: 0.804 -> 100.
  // Map order: cell (x, y) is image column x, row 2 - y; index x + 4 y.
  const std::vector<std::int8_t> expected = {100, 0,   0,  100,  // y = 0: row 2 (100 254 255 50)
                                             -1,  -1,  0,  0,    // y = 1: row 1
                                             100, 100, -1, -1};  // y = 2: row 0 (0 101 102 103)
  REQUIRE(values(yaml(MapMode::trinary, false, 0.6, 0.2)) == expected);
}

TEST_CASE("negate: p = v / 255, exactly at the thresholds is unknown", "[ros_map][values]") {
  // v / 255 is the correctly rounded quotient, so 51 -> 0.2 and 153 -> 0.6 are the thresholds'
  // own doubles: neither below nor above. v = 50 -> 0.196 free; 154 -> 0.604 occupied.
  const auto m = yaml(MapMode::trinary, true, 0.6, 0.2);
  const auto grid = occupancy_grid(decode_pgm("P2 4 1 255 50 51 153 154", "n.pgm", 10), m);
  REQUIRE(grid.values == std::vector<std::int8_t>{0, -1, -1, 100});
  // The image of the first case, negated: 0 -> free, 254/255 -> occupied, 100 -> 0.39 unknown.
  REQUIRE(values(m) == std::vector<std::int8_t>{-1, 100, 100, 0,    // 100 254 255 50
                                                -1, 100, 100, 100,  // 153 203 204 205
                                                0, -1, -1, -1});    // 0 101 102 103
}

TEST_CASE("scale: between the thresholds, rint((p - free) / (occupied - free) * 100)",
          "[ros_map][values]") {
  // v = 102: (0.6 - 0.2) / 0.4 * 100 = 100 -> 100. v = 103: 99.02 -> 99. v = 153: 50.
  // v = 203: 0.98 -> 1. Outside the band as trinary.
  REQUIRE(values(yaml(MapMode::scale, false, 0.6, 0.2)) ==
          std::vector<std::int8_t>{100, 0, 0, 100, 50, 1, 0, 0, 100, 100, 100, 99});
}

TEST_CASE("raw: the pixel value itself when 0..100, else unknown", "[ros_map][values]") {
  // Thresholds and negate do not matter in raw mode.
  const std::vector<std::int8_t> expected = {100, -1, -1, 50, -1, -1, -1, -1, 0, -1, -1, -1};
  REQUIRE(values(yaml(MapMode::raw, false, 0.6, 0.2)) == expected);
  REQUIRE(values(yaml(MapMode::raw, true, 0.9, 0.1)) == expected);
}

TEST_CASE("16-bit PGM: shade = value / maxval", "[ros_map][values]") {
  // maxval 1000: 390 -> p = 0.61 > 0.6 occupied; 400 -> 0.6 unknown; 810 -> 0.19 free.
  std::string bytes = "P5 3 1 1000\n";
  for (int v : {390, 400, 810}) {
    bytes.push_back(static_cast<char>(v >> 8));
    bytes.push_back(static_cast<char>(v & 0xFF));
  }
  const auto img = decode_pgm(bytes, "deep.pgm", 10);
  REQUIRE(img.pixels == std::vector<std::uint16_t>{390, 400, 810});
  REQUIRE(occupancy_grid(img, yaml(MapMode::trinary, false, 0.6, 0.2)).values ==
          std::vector<std::int8_t>{100, -1, 0});
}

TEST_CASE("PGM headers: comments, both magics, refusals name the file", "[ros_map][pgm]") {
  const auto a = decode_pgm("P5\n# a comment\n2 1\n# another\n255\n\x01\x02", "c.pgm", 10);
  REQUIRE(a.pixels == std::vector<std::uint16_t>{1, 2});
  auto refused = [](const std::string& bytes, const std::string& words) {
    try {
      (void)decode_pgm(bytes, "bad.pgm", 100);
      FAIL("accepted " << bytes);
    } catch (const flipper::sdk::Error& e) {
      INFO(e.what());
      REQUIRE(std::string(e.what()).find("bad.pgm: ") == 0);
      REQUIRE(std::string(e.what()).find(words) != std::string::npos);
    }
  };
  refused("P6\n2 1\n255\nabcdef", "must start with P5 or P2");
  refused("GIF89a", "must start with P5 or P2");
  refused("P5\n2 2\n255\n\x01\x02\x03", "truncated: 4 bytes of pixels expected (2 x 2), 3 found");
  refused("P5\n2 2\n", "truncated header: no maxval");
  refused("P5\n2 1\n0\n\x01\x02", "maxval is 0");
  refused("P5\n2 1\n70000\n", "maxval 70000 is above 65535");
  refused("P2\n2 1\n9\n3 10", "pixel 10 is above 9");
  refused("P2\n3 1\n9\n3 4", "truncated: 3 pixels expected, 2 found");
  refused("P5\n0 7\n255\n", "the image is empty");
}
