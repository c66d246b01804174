#pragma once
/// @file sidecar.hpp
/// The metre-denominated parts of a ros_map world file (docs/ros-maps.md, "The world file"):
/// `start` (the robot, metres), `objects` (items at metre positions) and `regions` (named
/// polygons in metres, each bound to a core-language room id), turned into the protocol's cell
/// fields (`robot`, `items`, `rooms`) on the map's grid.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::plugins::ros_map {

/// The map frame: cell (x, y) covers [origin + x * resolution, origin + (x + 1) * resolution)
/// on each axis; its centre is origin + (x + 0.5) * resolution.
struct MapFrame {
  double resolution = 1;
  double origin_x = 0;
  double origin_y = 0;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  double centre_x(std::int32_t x) const { return origin_x + (x + 0.5) * resolution; }
  double centre_y(std::int32_t y) const { return origin_y + (y + 0.5) * resolution; }
  /// The cell holding the point, if it lies on the map.
  bool cell_of(double mx, double my, sdk::Cell& out) const;
  /// "(12.3 m, 4.5 m)".
  static std::string metres(double mx, double my);
};

/// Rewrites `world` in place: `start` becomes `robot`, `objects` are appended to `items`, and
/// `regions` become rooms (returned, to merge after the protocol fields are parsed). Positions
/// must lie on free cells of `geometry`; a region's room is its free cells whose centre lies
/// inside its polygon (even-odd rule). Throws sdk::Error(bad_world) naming the entry and its
/// metres.
sdk::RoomMap convert_metre_fields(nlohmann::json& world, const MapFrame& frame,
                                  const sdk::Geometry& geometry);

}  // namespace flipper::plugins::ros_map
