// A /sempre context as a protocol world object (see sempre_world.hpp).
#include "sempre_world.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
namespace {

using Json = nlohmann::json;

[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadWorld, "context: " + where + " " + what);
}

std::int64_t coordinate(const Json& v, const std::string& where) {
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e9)
      return static_cast<std::int64_t>(d);
  }
  bad(where, "must be an integer coordinate, not " + v.dump());
}

std::string word(const Json& v, const std::string& where) {
  if (!v.is_string() || v.get<std::string>().empty())
    bad(where, "must be a colour or shape word, not " + v.dump());
  return v.get<std::string>();
}

const Json& member(const Json& root, const char* key) {
  auto it = root.find(key);
  if (it == root.end()) bad(std::string("'") + key + "'", "is missing");
  return *it;
}

}  // namespace

std::string sempre_context_world(std::string_view context_json) {
  const Json root = Json::parse(context_json, nullptr, false);
  if (root.is_discarded() || !root.is_object())
    bad("the world", "must be a JSON object with robot, world and rooms");
  Json out = Json::object();

  const Json& robot = member(root, "robot");
  if (!robot.is_array() || robot.size() != 3 || !robot[2].is_array())
    bad("robot", "must be [x, y, [[color, shape], ...]]");
  Json holding = Json::array();
  for (std::size_t i = 0; i < robot[2].size(); ++i) {
    const Json& h = robot[2][i];
    const std::string at = "robot's carried item " + std::to_string(i + 1);
    if (!h.is_array() || h.size() != 2) bad(at, "must be [color, shape]");
    holding.push_back({{"color", word(h[0], at)}, {"shape", word(h[1], at)}});
  }

  const Json& world = member(root, "world");
  if (!world.is_array()) bad("world", "must be a list of [x, y, type, color, shape]");
  Json walls = Json::array(), items = Json::array();
  for (std::size_t i = 0; i < world.size(); ++i) {
    const Json& e = world[i];
    const std::string at = "world entry " + std::to_string(i + 1);
    if (!e.is_array() || e.size() != 5 || !e[2].is_string())
      bad(at, "must be [x, y, \"wall\"|\"item\", color, shape], not " + e.dump());
    const std::int64_t x = coordinate(e[0], at), y = coordinate(e[1], at);
    const std::string type = e[2].get<std::string>();
    if (type == "wall")
      walls.push_back({x, y});
    else if (type == "item")
      items.push_back({{"x", x}, {"y", y}, {"color", word(e[3], at)}, {"shape", word(e[4], at)}});
    else
      bad(at, "has type '" + type + "'; a context world holds walls and items");
  }

  const Json& rooms = member(root, "rooms");
  if (!rooms.is_object()) bad("rooms", "must map each room name to its list of [x, y] cells");
  Json room_cells = Json::object();
  for (auto it = rooms.begin(); it != rooms.end(); ++it) {
    const std::string at = "room '" + it.key() + "'";
    if (!it.value().is_array()) bad(at, "must be a list of [x, y] cells");
    Json cells = Json::array();
    for (const Json& c : it.value()) {
      if (!c.is_array() || c.size() != 2) bad(at, "has a cell that is not [x, y]: " + c.dump());
      cells.push_back({coordinate(c[0], at), coordinate(c[1], at)});
    }
    room_cells[it.key()] = std::move(cells);
  }

  out["walls"] = std::move(walls);
  out["items"] = std::move(items);
  out["robot"] = {{"x", coordinate(robot[0], "robot")},
                  {"y", coordinate(robot[1], "robot")},
                  {"holding", std::move(holding)}};
  out["rooms"] = std::move(room_cells);
  return out.dump();
}

}  // namespace flipper::studio
