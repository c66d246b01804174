// The ros_map world plugin end to end: map files -> free mask, metres -> cells, inflation,
// regions, and what it refuses (docs/ros-maps.md).
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"
#include "ros_map_support.hpp"
#include "sanitizer_build.hpp"

using namespace flipper;
using namespace flipper::rosmaptest;
using sdk::Cell;

namespace {

// 4 x 3 at 0.5 m, origin (-1, 2): cell (x, y) covers x in [-1 + 0.5x, -0.5 + 0.5x) metres.
// The top-right pixel (column 3, row 0 -> cell (3, 2)) is occupied, (0, 2) unknown.
std::string small_map(const std::string& name, const std::string& extra_yaml = "") {
  const std::string dir = scratch_dir(name);
  write(dir, "m.pgm", p5({{205, 254, 254, 0}, {254, 254, 254, 254}, {254, 254, 254, 254}}));
  write(dir, "m.yaml", map_yaml("m.pgm", 0.5, "[-1.0, 2.0, 0.0]", 0, 0.65, 0.196, extra_yaml));
  return dir;
}

sdk::WorldState load(const std::string& dir, const std::string& json, const sdk::Params& p = {}) {
  return world(p)->load(json, dir);
}

void refused(const std::string& dir, const std::string& json, const std::string& words,
             const char* code = sdk::codes::kBadWorld, const sdk::Params& p = {}) {
  try {
    (void)load(dir, json, p);
    FAIL("accepted " << json);
  } catch (const sdk::Error& e) {
    INFO(e.what());
    REQUIRE(std::string(e.code()) == code);
    REQUIRE(std::string(e.what()).find(words) != std::string::npos);
  }
}

long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

}  // namespace

TEST_CASE("metres to cells: start, objects and regions on the map frame", "[ros_map][frame]") {
  const std::string dir = small_map("frame");
  const auto s = load(dir, R"({"map": "m.yaml", "start": {"x": -0.75, "y": 2.0},
    "objects": [{"x": 0.99, "y": 2.99, "color": "red", "shape": "circle"}],
    "regions": [{"room": "room2", "name": "corner",
                 "polygon": [[-1.0, 2.0], [0.01, 2.0], [0.01, 3.0], [-1.0, 3.0]]}]})");
  const sdk::Geometry& g = *s.geometry;
  REQUIRE(g.min() == Cell{0, 0, 0});
  REQUIRE(g.max() == Cell{3, 2, 0});
  // Image row 0 is the top: pixel (column 0, row 0) = 205 is cell (0, 2), unknown; pixel
  // (3, 0) = 0 is cell (3, 2), occupied; the rest is free.
  std::vector<std::uint8_t> expected(12, 1);
  expected[0 + 4 * 2] = 0;
  expected[3 + 4 * 2] = 0;
  REQUIRE(g.free_mask() == expected);
  REQUIRE(s.robot == Cell{0, 0, 0});  // x: floor((-0.75 + 1) / 0.5) = 0; y: floor(0 / 0.5) = 0
  REQUIRE(s.items.size() == 1);
  REQUIRE(s.items[0].at == Cell{3, 1, 0});  // floor(1.99 / 0.5) = 3, floor(0.99 / 0.5) = 1
  REQUIRE(s.items[0].item.color == "red");
  // Centres inside x <= 0.01, 2 <= y <= 3: x -0.75, -0.25 and y 2.25, 2.75.
  REQUIRE(s.rooms->at("room2") == sdk::Area{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}});
}

TEST_CASE("the map's edge in metres: last cell in, first metre out", "[ros_map][frame]") {
  const std::string dir = small_map("edge");
  // Width 4 x 0.5 m from x = -1: [-1, 1); height 3 x 0.5 m from y = 2: [2, 3.5).
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0.999, "y": 3.0}})",
          "start (0.999 m, 3 m) is on a blocked cell (3,2)");
  REQUIRE(load(dir, R"({"map": "m.yaml", "start": {"x": 0.999, "y": 2.999}})").robot ==
          Cell{3, 1, 0});
  refused(dir, R"({"map": "m.yaml", "start": {"x": 1.0, "y": 2.5}})",
          "start (1 m, 2.5 m) is outside the map (x from (-1 m, 2 m) to (1 m, 3.5 m))");
  refused(dir, R"({"map": "m.yaml", "start": {"x": -1.001, "y": 2.5}})", "is outside the map");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0.0, "y": 3.5}})", "is outside the map");
}

TEST_CASE("save and reload: cells, the map path and the frame in metres", "[ros_map][frame]") {
  const std::string dir = small_map("save");
  const auto w = world();
  const auto s = w->load(R"({"map": "m.yaml", "start": {"x": 0.25, "y": 2.25}})", dir);
  const std::string saved = w->save(s);
  const auto j = nlohmann::json::parse(saved);
  REQUIRE(j["map"] == dir + "/m.yaml");
  REQUIRE(j["frame"]["resolution"] == 0.5);
  REQUIRE(j["frame"]["origin"] == nlohmann::json::array({-1.0, 2.0}));
  REQUIRE(j["robot"]["x"] == 2);
  REQUIRE(j["bounds"]["max"] == nlohmann::json::array({3, 2}));
  const auto again = w->load(saved, "/");
  REQUIRE(again.robot == s.robot);
  REQUIRE(w->save(again) == saved);
}

TEST_CASE("inflation: blocked within the radius, centre to centre, boundary included",
          "[ros_map][inflation]") {
  // 9 x 9 free cells at 0.1 m with one occupied pixel in the middle (cell (4, 4)).
  const std::string dir = scratch_dir("inflation");
  std::vector<std::vector<int>> rows(9, std::vector<int>(9, 254));
  rows[4][4] = 0;
  write(dir, "m.pgm", p5(rows));
  write(dir, "m.yaml", map_yaml("m.pgm", 0.1, "[0, 0, 0]", 0, 0.65, 0.196));
  const std::string json = R"({"map": "m.yaml", "start": {"x": 0.05, "y": 0.05}})";
  auto free_count = [&](double r) {
    return load(dir, json, params(r)).geometry->free_cells().size();
  };
  // Offsets (dx, dy) with dx^2 + dy^2 <= R^2: R = 1.9 -> 9 (0, 1, sqrt 2); R = 2 -> 13 (+ the
  // four at distance 2, exactly on the radius); R = 2.236 -> 13 (sqrt 5 = 2.2361 just outside);
  // R = 2.237 -> 21 (+ the eight at sqrt 5).
  REQUIRE(free_count(0.0) == 80);
  REQUIRE(free_count(0.19) == 81 - 9);
  REQUIRE(free_count(0.2) == 81 - 13);
  REQUIRE(free_count(0.2236) == 81 - 13);
  REQUIRE(free_count(0.2237) == 81 - 21);
  const auto g = load(dir, json, params(0.2)).geometry;
  REQUIRE(!g->is_free({6, 4, 0}));  // distance 2: on the radius
  REQUIRE(g->is_free({6, 5, 0}));   // sqrt 5
  REQUIRE(!g->is_free({5, 5, 0}));  // sqrt 2
}

TEST_CASE("inflation spreads from occupied cells, from unknown ones only when asked",
          "[ros_map][inflation]") {
  const std::string dir = scratch_dir("inflate_unknown");
  std::vector<std::vector<int>> rows(5, std::vector<int>(5, 254));
  rows[2][2] = 205;  // unknown: p = 0.196, not below free_thresh 0.196
  write(dir, "m.pgm", p5(rows));
  write(dir, "m.yaml", map_yaml("m.pgm", 1.0, "[0, 0, 0]", 0, 0.65, 0.196));
  const std::string json = R"({"map": "m.yaml", "start": {"x": 0.5, "y": 0.5}})";
  REQUIRE(load(dir, json, params(1.0)).geometry->free_cells().size() == 24);
  REQUIRE(load(dir, json, params(1.0, true)).geometry->free_cells().size() == 20);
}

TEST_CASE("scale and raw maps: a cell is blocked from lethal_threshold, and when unknown",
          "[ros_map][modes]") {
  const std::string dir = scratch_dir("lethal");
  // raw: the pixel is the value. 0, 49, 50, 99, 100 and 101 (unknown in raw mode).
  write(dir, "m.pgm", p5({{0, 49, 50, 99, 100, 101}}));
  write(dir, "m.yaml", map_yaml("m.pgm", 1.0, "[0, 0, 0]", 0, 0.65, 0.196, "mode: raw\n"));
  const std::string json = R"({"map": "m.yaml", "start": {"x": 0.5, "y": 0.5}})";
  auto mask = [&](int lethal) {
    return load(dir, json, params(0, false, lethal)).geometry->free_mask();
  };
  REQUIRE(mask(100) == std::vector<std::uint8_t>{1, 1, 1, 1, 0, 0});
  REQUIRE(mask(50) == std::vector<std::uint8_t>{1, 1, 0, 0, 0, 0});
  REQUIRE(mask(1) == std::vector<std::uint8_t>{1, 0, 0, 0, 0, 0});
  // scale: the band between the thresholds is traversable (Nav2 costs it; it is not unknown).
  write(dir, "s.yaml", map_yaml("s.pgm", 1.0, "[0, 0, 0]", 0, 0.6, 0.2, "mode: scale\n"));
  write(dir, "s.pgm", p5({{254, 153, 103, 102}}));  // values 0, 50, 99, 100
  const std::string sj = R"({"map": "s.yaml", "start": {"x": 0.5, "y": 0.5}})";
  REQUIRE(load(dir, sj).geometry->free_mask() == std::vector<std::uint8_t>{1, 1, 1, 0});
  REQUIRE(load(dir, sj, params(0, false, 50)).geometry->free_mask() ==
          std::vector<std::uint8_t>{1, 0, 0, 0});
  // The same pixels in trinary mode: 153 and 103 are unknown, never planned through.
  write(dir, "t.yaml", map_yaml("s.pgm", 1.0, "[0, 0, 0]", 0, 0.6, 0.2));
  REQUIRE(load(dir, R"({"map": "t.yaml", "start": {"x": 0.5, "y": 0.5}})").geometry->free_mask() ==
          std::vector<std::uint8_t>{1, 0, 0, 0});
}

TEST_CASE("bad map files are refused naming the file and what is wrong", "[ros_map][refusals]") {
  const std::string dir = small_map("bad");
  const std::string j = R"({"map": "m.yaml", "start": {"x": 0.25, "y": 2.25}})";
  auto yaml_says = [&](const std::string& yaml, const std::string& words) {
    write(dir, "m.yaml", yaml);
    refused(dir, j, dir + "/m.yaml: " + words);
  };
  yaml_says(map_yaml("m.pgm", 0.5, "[-1.0, 2.0, 0.5]", 0, 0.65, 0.196),
            "'origin' yaw is 0.5; only maps with yaw 0 are supported");
  yaml_says(map_yaml("m.pgm", 0.5, "[-1.0, 2.0]", 0, 0.65, 0.196), "'origin' must be [x, y, yaw]");
  yaml_says(map_yaml("m.pgm", 0, "[0, 0, 0]", 0, 0.65, 0.196), "'resolution' must be a positive");
  yaml_says(map_yaml("m.pgm", 0.5, "[0, 0, 0]", 0, 0.65, 0.196, "mode: fuzzy\n"),
            "'mode' is 'fuzzy'; expected trinary, scale or raw");
  yaml_says(map_yaml("m.pgm", 0.5, "[0, 0, 0]", 0, 0.2, 0.6),
            "'free_thresh' (0.600000) must not exceed");
  yaml_says("image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 0\nfree_thresh: 0.2\n",
            "missing key 'occupied_thresh'");
  yaml_says("image: [m.pgm]\n", "'image' must be a file name");
  yaml_says("image: m.pgm\nresolution: fine\n", "'resolution' must be a number, got 'fine'");
  yaml_says("{{{", "not valid YAML");
  write(dir, "m.yaml", map_yaml("gone.pgm", 0.5, "[0, 0, 0]", 0, 0.65, 0.196));
  refused(dir, j, "map image: cannot read file " + dir + "/gone.pgm");
  write(dir, "m.yaml", map_yaml("m.pgm", 0.5, "[-1.0, 2.0, 0.0]", 0, 0.65, 0.196));

  write(dir, "m.pgm", "P6\n4 3\n255\n");
  refused(dir, j, dir + "/m.pgm: not a PGM image (the file must start with P5 or P2)");
  write(dir, "m.pgm", "P5\n4 3\n255\n\xfe\xfe\xfe\xfe\xfe");
  refused(dir, j, dir + "/m.pgm: truncated: 12 bytes of pixels expected (4 x 3), 5 found");
  std::filesystem::create_directory(dir + "/dir.yaml");
  refused(dir, R"({"map": "dir.yaml"})", "is not a regular file", sdk::codes::kNotARegularFile);
  refused(dir, R"({"map": "none.yaml"})", "map: cannot read file " + dir + "/none.yaml");
  refused(dir, R"({"start": {"x": 0, "y": 0}, "robot": {"x": 0, "y": 0}})", "map: missing");
}

TEST_CASE("huge dimensions are refused from the header, in bounded time and memory",
          "[ros_map][refusals]") {
  const std::string dir = small_map("huge");
  // 60000 x 60000 = 3.6e9 cells in a 20-byte header: refused before any pixel is stored.
  write(dir, "m.pgm", "P5\n60000 60000\n255\n");
  const long before = peak_rss_kib();
  const auto t0 = std::chrono::steady_clock::now();
  refused(dir, R"({"map": "m.yaml"})",
          "60000 x 60000 = 3600000000 cells; the limit is max_cells = 4194304",
          sdk::codes::kWorldTooLarge);
  // 2049 x 2048 = 4196352: one row over the default limit (2048 x 2048 = 4194304 is the limit).
  write(dir, "m.pgm", "P5\n2049 2048\n255\n");
  refused(dir, R"({"map": "m.yaml"})", "= 4196352 cells", sdk::codes::kWorldTooLarge);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE(seconds < 2.0);  // microseconds of work; 2 s only stops a runaway
  // Nothing near 4 MiB (let alone 3.6 GB) allocated; instrumented, ASan's own bookkeeping and
  // the -O0 test code's stack add a few hundred KiB (4,240 KiB measured), so 16 MiB there.
  REQUIRE(peak_rss_kib() - before < (flipper::testsupport::kAddressSanitizer ? 16384 : 4096));
  // max_cells at N and N + 1: a 4 x 3 image loads with max_cells 12, a 13 x 1 one does not.
  sdk::Params twelve = params(0);
  twelve.set("max_cells", std::int64_t{12});
  write(dir, "m.pgm", p5(std::vector<std::vector<int>>(3, std::vector<int>(4, 254))));
  REQUIRE(load(dir, R"({"map": "m.yaml", "start": {"x": -0.75, "y": 2.25}})", twelve)
              .geometry->cell_count() == 12);
  write(dir, "m.pgm", p5({std::vector<int>(13, 254)}));
  refused(dir, R"({"map": "m.yaml"})", "13 x 1 = 13 cells; the limit is max_cells = 12",
          sdk::codes::kWorldTooLarge, twelve);
  // The file bound: max_file_bytes below the image's size.
  // The file bound: max_file_bytes between the YAML's size (105 bytes) and the image's (213).
  write(dir, "m.pgm", p5(std::vector<std::vector<int>>(10, std::vector<int>(20, 254))));
  sdk::Params small = params(0);
  small.set("max_file_bytes", std::int64_t{150});
  refused(dir, R"({"map": "m.yaml"})", "m.pgm has 213 bytes; the limit is max_file_bytes = 150",
          sdk::codes::kFileTooLarge, small);
}

TEST_CASE("metre fields are checked and named", "[ros_map][refusals]") {
  const std::string dir = small_map("fields");
  refused(dir, R"({"map": "m.yaml", "start": {"x": -0.75, "y": 3.25}})",
          "start (-0.75 m, 3.25 m) is on a blocked cell (0,2) (occupied, unknown");
  refused(dir, R"({"map": "m.yaml", "start": {"x": "a", "y": 2}})", "start: x must be a number");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2}, "robot": {"x": 0, "y": 0}})",
          "start and robot");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2},
                   "objects": [{"x": 0.9, "y": 3.4, "color": "red", "shape": "circle"}]})",
          "objects[0] (0.9 m, 3.4 m) is on a blocked cell (3,2)");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2},
                   "regions": [{"room": "kitchen", "polygon": [[0,2],[1,2],[1,3]]}]})",
          "regions[0]: room 'kitchen' is not a room id");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2},
                   "regions": [{"room": "room1", "polygon": [[0,2],[1,2]]}]})",
          "regions[0] (room1): polygon must list at least 3 points");
  // A polygon around the occupied cell (3, 2) only (centre (0.75, 3.25)): no free cell.
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2},
                   "regions": [{"room": "room1", "polygon": [[0.6,3.1],[0.9,3.1],[0.9,3.4],[0.6,3.4]]}]})",
          "regions[0] (room1): no free cell has its centre inside the polygon");
  refused(dir, R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2},
                   "regions": [{"room": "room1", "polygon": [[-1,2],[0,2],[0,3]]},
                               {"room": "room1", "polygon": [[-1,2],[0,2],[0,3]]}]})",
          "regions[1] (room1): duplicate room id 'room1'");
  refused(
      dir,
      R"({"map": "m.yaml", "start": {"x": 0, "y": 2.2}, "bounds": {"min": [0, 0], "max": [9, 9]}})",
      "differ from the map's");
}
