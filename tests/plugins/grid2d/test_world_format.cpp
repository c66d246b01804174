// The SDK's world_format helpers on their own, in 3-D (the grid2d tests cover 2-D through the
// plugin): what a 3-D world plugin relies on.
#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world_format.hpp"

using namespace flipper::sdk;
namespace wf = flipper::sdk::world_format;

TEST_CASE("world_format reads 3-D points, keeps extra fields and writes z", "[world_format]") {
  wf::WorldDocument doc = wf::parse_world(
      R"({"octomap": "map.bt", "resolution": 0.05, "walls": [[1, 1, 1]],
          "items": [{"x": 0, "y": 1, "z": 2, "color": "red", "shape": "cube"}],
          "robot": {"x": 0, "y": 0, "z": 0}, "rooms": {"lab": [[0, 0, 2], [0, 0, 1]]}})",
      3);
  REQUIRE(doc.octomap == std::optional<std::string>("map.bt"));
  REQUIRE(doc.extra.at("resolution") == "0.05");
  REQUIRE(doc.walls == std::vector<Cell>{{1, 1, 1}});
  REQUIRE(doc.items.at(0).at == Cell{0, 1, 2});
  REQUIRE(doc.rooms.at("lab") == Area{{0, 0, 1}, {0, 0, 2}});
  const wf::Bounds box = wf::effective_bounds(doc);
  REQUIRE(box == wf::Bounds{{0, 0, 0}, {1, 1, 2}});
  std::vector<std::uint8_t> mask(2 * 2 * 3, 1);
  auto g = std::make_shared<const Geometry>(
      3, box.min, box.max, mask,
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      std::vector<std::pair<std::string, Cell>>{});
  wf::check_placement(doc, *g);
  const WorldState s = wf::make_state(std::move(doc), g);
  REQUIRE(
      wf::write_world(s, {{"octomap", "\"map.bt\""}}) ==
      R"({"octomap":"map.bt","items":[{"id":0,"x":0,"y":1,"z":2,"color":"red","shape":"cube"}],)"
      R"("robot":{"x":0,"y":0,"z":0,"holding":[]},"rooms":{"lab":[[0,0,1],[0,0,2]]},)"
      R"("bounds":{"min":[0,0,0],"max":[1,1,2]}})");
  REQUIRE(wf::points_json({{1, 2, 3}}, 3) == "[[1,2,3]]");
  REQUIRE(wf::points_json({{1, 2, 3}}, 2) == "[[1,2]]");
}

TEST_CASE("world_format names the entry in 3-D errors", "[world_format]") {
  auto message = [](const std::string& text) {
    try {
      (void)wf::parse_world(text, 3);
    } catch (const Error& e) {
      CHECK(e.code() == codes::kBadWorld);
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(message(R"({"robot": {"x": 0, "y": 0}})") == "robot: missing \"z\"");
  CHECK(message(R"({"robot": {"x": 0, "y": 0, "z": 0}, "walls": [[1, 2]]})") ==
        "walls[0]: a point must be an array of 3 integers");
  CHECK(message(R"({"robot": {"x": 0, "y": 0, "z": 0}, "octomap": 3})") ==
        "octomap must be a file name (string), not an integer");
  CHECK(message(R"({"robot": {"x": 0, "y": 0, "z": 99999999999}})")
            .find("robot: z is out of range") == 0);
}

TEST_CASE("world_format reads wall lists exactly, well-formed or not", "[world_format]") {
  auto parse = [](const std::string& walls) {
    try {
      auto doc = wf::parse_world(R"({"robot": {"x": 0, "y": 0}, "walls": )" + walls + "}", 2);
      std::string out;
      for (const auto& c : doc.walls) out += wf::describe(c, 2);
      return out;
    } catch (const Error& e) {
      return std::string(e.what());
    }
  };
  // Sorted and without duplicates; negative and limit coordinates are kept.
  CHECK(parse("[[3, 1], [-2, 5], [3, 1], [268435456, -268435456]]") ==
        "(-2,5)(3,1)(268435456,-268435456)");
  CHECK(parse("[]").empty());
  // Each defect is named with the point's index, wherever it is in the list.
  CHECK(parse("[[0, 0], [1, 268435457]]").find("walls[1]: y is out of range") == 0);
  CHECK(parse("[[0, 0], [1, 2.5]]") == "walls[1]: y must be an integer, not a fractional number");
  CHECK(parse("[[0, 0], [1, 2, 3]]") == "walls[1]: a point must be an array of 2 integers");
  CHECK(parse("[[0, 0], [1]]") == "walls[1]: a point must be an array of 2 integers");
  CHECK(parse("[[0, 0], {\"x\": 1}]") == "walls[1]: a point must be an array of 2 integers");
  CHECK(parse("[[0, 0], [[1, 2]]]") == "walls[1]: a point must be an array of 2 integers");
  CHECK(parse("{\"a\": [1, 2]}") == "walls must be an array of points, not an object");
  CHECK(parse("[[0, 0], [\"1\", 2]]") == "walls[1]: x must be an integer, not a string");
}

TEST_CASE("world_format says when a world reads in the other dimensions", "[world_format]") {
  auto dims_of_refusal = [](const std::string& text, int dims, std::string& message) {
    try {
      (void)wf::parse_world(text, dims);
    } catch (const flipper::sdk::OtherDimsError& e) {
      CHECK(e.code() == codes::kBadWorld);
      message = e.what();
      return e.world_dims();
    } catch (const Error& e) {
      CHECK(e.code() == codes::kBadWorld);
      message = e.what();
      return 0;
    }
    return -1;
  };
  std::string message;
  // A 3-D world for a 2-D reader: the reader's own message, the world's dimensions.
  CHECK(dims_of_refusal(R"({"robot": {"x": 0, "y": 0, "z": 0}, "walls": [[1, 2, 3]]})", 2,
                        message) == 3);
  CHECK(message == "walls[0]: a point must be an array of 2 integers");
  CHECK(dims_of_refusal(R"({"robot": {"x": 0, "y": 0}, "walls": [[1, 2]]})", 3, message) == 2);
  CHECK(message == "walls[0]: a point must be an array of 3 integers");  // walls are read first
  // Malformed in both: a plain bad_world.
  CHECK(dims_of_refusal(R"({"robot": {"x": 0, "y": 0}, "walls": [[1]]})", 3, message) == 0);
  CHECK(message == "walls[0]: a point must be an array of 3 integers");
  CHECK(dims_of_refusal(R"({"robot": {"x": 0, "y": 0}, "walls": [[1]]})", 2, message) == 0);
  // Well-formed: accepted.
  CHECK(dims_of_refusal(R"({"robot": {"x": 0, "y": 0}, "walls": [[1, 2]]})", 2, message) == -1);
}
