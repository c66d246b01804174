#include "obstacles.hpp"

#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::octomap3d {
namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& what) {
  throw sdk::Error(sdk::codes::kBadWorld, what);
}

sdk::Cell point(const json& v, const std::string& where) {
  if (v.is_array() && v.size() == 2)
    bad(where + " is a 2-D point " + v.dump() + "; this 3-D world needs [x, y, z]");
  if (!v.is_array() || v.size() != 3) bad(where + " must be a point [x, y, z], got " + v.dump());
  sdk::Cell c;
  std::int32_t* out[3] = {&c.x, &c.y, &c.z};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number_integer() || v[i].get<std::int64_t>() < -1000000 ||
        v[i].get<std::int64_t>() > 1000000)
      bad(where + " must hold integers in [-1000000, 1000000], got " + v.dump());
    *out[i] = static_cast<std::int32_t>(v[i].get<std::int64_t>());
  }
  return c;
}

json cell_json(sdk::Cell c) {
  return json::array({c.x, c.y, c.z});
}

}  // namespace

Obstacles take_obstacles(wf::WorldDocument& doc) {
  Obstacles out;
  out.walls = doc.walls;
  out.octomap = doc.octomap;
  for (const auto& [key, text] : doc.extra) {
    if (key != "boxes") bad("unknown entry \"" + key + "\" in a 3-D world");
    const json boxes = json::parse(text);
    if (!boxes.is_array()) bad("boxes must be a list of {\"min\": [x, y, z], \"max\": [x, y, z]}");
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const std::string where = "boxes[" + std::to_string(i) + "]";
      const json& b = boxes[i];
      if (!b.is_object() || !b.contains("min") || !b.contains("max"))
        bad(where + " must be {\"min\": [x, y, z], \"max\": [x, y, z]}, got " + b.dump());
      CellBox box{point(b["min"], where + ".min"), point(b["max"], where + ".max")};
      if (box.min.x > box.max.x || box.min.y > box.max.y || box.min.z > box.max.z)
        bad(where + " has min > max: " + b.dump());
      out.boxes.push_back(box);
    }
  }
  return out;
}

std::vector<wf::RawField> obstacle_fields(const Obstacles& obstacles) {
  std::vector<wf::RawField> fields;
  if (obstacles.octomap) fields.push_back({"octomap", json(*obstacles.octomap).dump()});
  if (!obstacles.boxes.empty()) {
    json boxes = json::array();
    for (const auto& b : obstacles.boxes)
      boxes.push_back({{"min", cell_json(b.min)}, {"max", cell_json(b.max)}});
    fields.push_back({"boxes", boxes.dump()});
  }
  if (!obstacles.walls.empty()) fields.push_back({"walls", wf::points_json(obstacles.walls, 3)});
  return fields;
}

}  // namespace flipper::plugins::octomap3d
