// The SDK's world_format helpers on their own, in 3-D (the grid2d tests cover 2-D through the
// plugin): what a 3-D world plugin relies on.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

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

namespace {

// Every field of a document, as text: two parses agree when their descriptions do.
std::string describe_document(const wf::WorldDocument& d) {
  std::string out = "dims " + std::to_string(d.dims) + " has_walls " + std::to_string(d.has_walls);
  out += "\nwalls ";
  for (const auto& c : d.walls) out += wf::describe(c, d.dims);
  out += "\noctomap " + d.octomap.value_or("-") + "\nitems ";
  for (const auto& i : d.items)
    out += std::to_string(i.item.id) + i.item.color + i.item.shape + wf::describe(i.at, d.dims);
  out += "\nrobot " + wf::describe(d.robot, d.dims) + "\nholding ";
  for (const auto& h : d.holding) out += std::to_string(h.id) + h.color + h.shape;
  out += "\nrooms ";
  for (const auto& [name, area] : d.rooms) {
    out += name + ":";
    for (const auto& c : area) out += wf::describe(c, d.dims);
  }
  out += "\nroom_points ";
  for (const auto& [name, points] : d.room_points) {
    out += name + ":";
    for (const auto& c : points) out += wf::describe(c, d.dims);
  }
  if (d.bounds)
    out += "\nbounds " + wf::describe(d.bounds->min, 3) + wf::describe(d.bounds->max, 3);
  out += "\nnext " + std::to_string(d.next_item_id) + "\nextra ";
  for (const auto& [k, v] : d.extra) out += k + "=" + v + ";";
  return out;
}

// The document, or the error's code and message.
std::string read_world(const std::string& text, int dims = 2) {
  try {
    return describe_document(wf::parse_world(text, dims));
  } catch (const Error& e) {
    return std::string("error ") + e.code() + ": " + e.what();
  }
}

// The same world with its "walls" and "rooms" keys spelled with an escape: the lists are then read
// only by the full parse (the point scanner declines a key with an escape), the oracle here.
std::string escaped_keys(std::string text) {
  for (const auto& [key, escaped] :
       {std::pair<std::string, std::string>{"\"walls\"", "\"wa\\u006cls\""},
        {"\"rooms\"", "\"roo\\u006ds\""}}) {
    const auto at = text.find(key);
    if (at != std::string::npos) text.replace(at, key.size(), escaped);
  }
  return text;
}

}  // namespace

TEST_CASE("world_format reads plain point lists from the text exactly as the full parse does",
          "[world_format]") {
  // The study's worlds, compact and pretty-printed.
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/worlds.jsonl");
  REQUIRE(in);
  std::string line;
  int worlds = 0, with_rooms = 0;
  while (std::getline(in, line)) {
    auto w = nlohmann::json::parse(line);
    nlohmann::json obj;
    for (const char* k : {"walls", "items", "robot", "rooms", "bounds"})
      if (w.contains(k)) obj[k] = w[k];
    with_rooms += obj.contains("rooms") && !obj["rooms"].empty();
    for (const std::string& text : {obj.dump(), obj.dump(2)}) {
      const std::string fast = read_world(text);
      REQUIRE(fast.rfind("error", 0) == std::string::npos);
      REQUIRE(fast == read_world(escaped_keys(text)));
    }
    ++worlds;
  }
  CHECK(worlds == 1088);
  CHECK(with_rooms > 500);

  const std::string robot = R"("robot": {"x": 0, "y": 0})";
  auto same = [&](const std::string& text, int dims = 2) {
    const std::string fast = read_world(text, dims);
    CHECK(fast == read_world(escaped_keys(text), dims));
    return fast;
  };
  // Spacing, order, limits, "-0", and look-alikes the scanner must step over.
  CHECK(same("{ \"walls\" :\n[ [ 3 ,1 ] ,\t[-2,5],[3,1],[268435456,-268435456],[-0,0]] ," + robot +
             R"(, "rooms": {"b": [[1, 1]], "a": [[2, 2], [0, 0]]}})")
            .find("walls (-2,5)(0,0)(3,1)(268435456,-268435456)\n") != std::string::npos);
  CHECK(same(R"({"note": {"walls": [[9, 9]], "x": "}"}, "s": "\"walls\": [[8,8]]", )" + robot +
             R"(, "walls": [[1, 2]], "n": -1.5e3, "t": true})")
            .find("walls (1,2)\n") != std::string::npos);
  CHECK(same(R"({"rooms": {}, "walls": [], )" + robot + "}").find("walls \n") != std::string::npos);
  CHECK(same(R"({"walls": [[1, 2, 3]], "robot": {"x": 0, "y": 0, "z": 0}})", 3)
            .find("walls (1,2,3)\n") != std::string::npos);
  // What the scanner declines is read by the full parse: its messages, its positions.
  CHECK(same(R"({"walls": [[1, 2]], "walls": [[3, 4]], )" + robot + "}") ==
        "error bad_world: duplicate key \"walls\"");
  CHECK(same(R"({"rooms": {"a": [[1, 2]], "a": [[3, 4]]}, )" + robot + "}") ==
        "error bad_world: rooms: duplicate room name \"a\"");
  CHECK(same(R"({"rooms": {"": [[1, 2]]}, )" + robot + "}") ==
        "error bad_world: rooms: a room name must not be empty");
  CHECK(same(R"({"walls": [[268435457, 0]], )" + robot + "}") ==
        "error bad_world: walls[0]: x is out of range (268435457)");
  CHECK(same(R"({"walls": [[0, 1.0]], )" + robot + "}") ==
        "error bad_world: walls[0]: y must be an integer, not a fractional number");
  CHECK(same(R"({"walls": [[0, 1e2]], )" + robot + "}") ==
        "error bad_world: walls[0]: y must be an integer, not a fractional number");
  CHECK(same(R"({"rooms": {"r": [[0, 0, 0]]}, )" + robot + "}") ==
        "error bad_world: rooms.r[0]: a point must be an array of 2 integers");
  CHECK(read_world(R"({"rooms": {"caf\u00e9": [[1, 2]]}, )" + robot + "}")
            .find("rooms café:(1,2)\n") != std::string::npos);
  CHECK(same(R"({"rooms": {"café": [[1, 2]]}, )" + robot + "}").find("rooms café:(1,2)\n") !=
        std::string::npos);
  // Syntax errors anywhere: nlohmann's own message for the text as sent (its byte position).
  for (const std::string& text :
       {R"({"walls": [[1, 2]], )" + robot, R"({"walls": [[01, 2]], )" + robot + "}",
        R"({"walls": [[1, 2]] )" + robot + "}",
        R"({"rooms": {"a": [[1, 2]]}, "x": [1,}, )" + robot + "}",
        std::string(R"({"walls": [[1, 2]], "s": "a)") + '\x01' + "\", " + robot + "}",
        std::string(R"({"walls": [[1, 2]], "rooms": {"a)") + '\x01' + "\": [[0, 0]]}, " + robot +
            "}"}) {
    std::string expected;
    try {
      const auto parsed = nlohmann::json::parse(text);  // throws: these texts are not JSON
      static_cast<void>(parsed);
    } catch (const nlohmann::json::exception& e) {
      expected = std::string("error bad_world: world is not valid JSON: ") + e.what();
    }
    REQUIRE_FALSE(expected.empty());
    CHECK(read_world(text) == expected);
  }
}
