#include "sidecar.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::ros_map {

namespace sdk = flipper::sdk;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw sdk::Error(sdk::codes::kBadWorld, what);
}

double number(const json& j, const std::string& where) {
  if (!j.is_number()) fail(where + " must be a number of metres");
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(where + " must be finite");
  return v;
}

std::string cell_text(const sdk::Cell& c) {
  return "cell (" + std::to_string(c.x) + "," + std::to_string(c.y) + ")";
}

// A metre position {"x": .., "y": ..} on a free cell.
sdk::Cell free_cell_at(const json& pos, const std::string& where, const MapFrame& frame,
                       const sdk::Geometry& geometry) {
  if (!pos.is_object() || !pos.contains("x") || !pos.contains("y"))
    fail(where + " must be an object with \"x\" and \"y\" in metres");
  const double mx = number(pos["x"], where + ": x");
  const double my = number(pos["y"], where + ": y");
  sdk::Cell c;
  if (!frame.cell_of(mx, my, c))
    fail(where + " " + MapFrame::metres(mx, my) + " is outside the map (x from " +
         MapFrame::metres(frame.origin_x, frame.origin_y) + " to " +
         MapFrame::metres(frame.origin_x + frame.width * frame.resolution,
                          frame.origin_y + frame.height * frame.resolution) +
         ")");
  if (!geometry.is_free(c))
    fail(where + " " + MapFrame::metres(mx, my) + " is on a blocked " + cell_text(c) +
         " (occupied, unknown, or within inflation_radius of an obstacle)");
  return c;
}

bool inside(const std::vector<std::pair<double, double>>& poly, double px, double py) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto [xi, yi] = poly[i];
    const auto [xj, yj] = poly[j];
    if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}

sdk::Area rasterize(const std::vector<std::pair<double, double>>& poly, const MapFrame& frame,
                    const sdk::Geometry& geometry) {
  double lo_x = poly[0].first, hi_x = lo_x, lo_y = poly[0].second, hi_y = lo_y;
  for (const auto& [x, y] : poly) {
    lo_x = std::min(lo_x, x);
    hi_x = std::max(hi_x, x);
    lo_y = std::min(lo_y, y);
    hi_y = std::max(hi_y, y);
  }
  // Cells whose centre may lie inside the polygon's box, clamped to the map.
  auto first = [&](double m, double origin, std::uint32_t n) {
    const double c = std::ceil((m - origin) / frame.resolution - 0.5);
    return static_cast<std::int64_t>(std::clamp(c, 0.0, double(n)));
  };
  auto last = [&](double m, double origin, std::uint32_t n) {
    const double c = std::floor((m - origin) / frame.resolution - 0.5);
    return static_cast<std::int64_t>(std::clamp(c, -1.0, double(n) - 1));
  };
  const std::int64_t x0 = first(lo_x, frame.origin_x, frame.width);
  const std::int64_t x1 = last(hi_x, frame.origin_x, frame.width);
  const std::int64_t y0 = first(lo_y, frame.origin_y, frame.height);
  const std::int64_t y1 = last(hi_y, frame.origin_y, frame.height);
  sdk::Area area;
  for (std::int64_t x = x0; x <= x1; ++x)
    for (std::int64_t y = y0; y <= y1; ++y) {
      const sdk::Cell c{static_cast<std::int32_t>(x), static_cast<std::int32_t>(y), 0};
      if (geometry.is_free(c) && inside(poly, frame.centre_x(c.x), frame.centre_y(c.y)))
        area.push_back(c);
    }
  sdk::areas::normalize(area);
  return area;
}

bool is_room_id(const std::string& s) {
  if (s.size() < 5 || s.compare(0, 4, "room") != 0) return false;
  return std::all_of(s.begin() + 4, s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

bool MapFrame::cell_of(double mx, double my, sdk::Cell& out) const {
  const double fx = std::floor((mx - origin_x) / resolution);
  const double fy = std::floor((my - origin_y) / resolution);
  if (!(fx >= 0 && fx < width && fy >= 0 && fy < height)) return false;
  out = {static_cast<std::int32_t>(fx), static_cast<std::int32_t>(fy), 0};
  return true;
}

std::string MapFrame::metres(double mx, double my) {
  std::ostringstream s;
  s << "(" << mx << " m, " << my << " m)";
  return s.str();
}

sdk::RoomMap convert_metre_fields(json& world, const MapFrame& frame,
                                  const sdk::Geometry& geometry) {
  if (world.contains("start")) {
    if (world.contains("robot"))
      fail("start and robot: give the robot once, in metres (start) or in cells (robot)");
    const json& start = world["start"];
    const sdk::Cell c = free_cell_at(start, "start", frame, geometry);
    json robot = {{"x", c.x}, {"y", c.y}};
    if (start.contains("holding")) robot["holding"] = start["holding"];
    world["robot"] = robot;
    world.erase("start");
  }
  if (world.contains("objects")) {
    const json& objects = world["objects"];
    if (!objects.is_array()) fail("objects must be an array of {x, y, color, shape} in metres");
    if (!world.contains("items")) world["items"] = json::array();
    if (!world["items"].is_array()) fail("items must be an array");
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const std::string where = "objects[" + std::to_string(i) + "]";
      const sdk::Cell c = free_cell_at(objects[i], where, frame, geometry);
      json item = objects[i];
      item["x"] = c.x;
      item["y"] = c.y;
      world["items"].push_back(item);
    }
    world.erase("objects");
  }
  sdk::RoomMap rooms;
  if (world.contains("regions")) {
    const json& regions = world["regions"];
    if (!regions.is_array())
      fail("regions must be an array of {room, name, polygon} (polygon in metres)");
    for (std::size_t i = 0; i < regions.size(); ++i) {
      const json& r = regions[i];
      std::string where = "regions[" + std::to_string(i) + "]";
      if (!r.is_object() || !r.contains("room") || !r["room"].is_string())
        fail(where + ": room must be a room id (room1, room2, ...)");
      const std::string room = r["room"].get<std::string>();
      if (!is_room_id(room))
        fail(where + ": room '" + room + "' is not a room id (room1, room2, ...)");
      if (r.contains("name") && !r["name"].is_string()) fail(where + ": name must be a string");
      where += " (" + room + ")";
      if (rooms.count(room) != 0) fail(where + ": duplicate room id '" + room + "'");
      if (!r.contains("polygon") || !r["polygon"].is_array() || r["polygon"].size() < 3)
        fail(where + ": polygon must list at least 3 points [x, y] in metres");
      std::vector<std::pair<double, double>> poly;
      for (std::size_t k = 0; k < r["polygon"].size(); ++k) {
        const json& p = r["polygon"][k];
        const std::string pw = where + ": polygon[" + std::to_string(k) + "]";
        if (!p.is_array() || p.size() != 2) fail(pw + " must be [x, y] in metres");
        poly.emplace_back(number(p[0], pw + "[0]"), number(p[1], pw + "[1]"));
      }
      sdk::Area area = rasterize(poly, frame, geometry);
      if (area.empty())
        fail(where + ": no free cell has its centre inside the polygon (a room must be reachable)");
      rooms.emplace(room, std::move(area));
    }
    world.erase("regions");
  }
  return rooms;
}

}  // namespace flipper::plugins::ros_map
