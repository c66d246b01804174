#pragma once
/// @file map_yaml.hpp
/// The map_server YAML of a ROS occupancy-grid map, read as Nav2's map_io reads it
/// (docs/ros-maps.md, "The map YAML").
#include <cstdint>
#include <string>

namespace flipper::plugins::ros_map {

enum class MapMode { trinary, scale, raw };

struct MapYaml {
  std::string image;      ///< the image path, resolved against the YAML's folder
  double resolution = 0;  ///< metres per cell, > 0
  double origin_x = 0;    ///< metres of the lower-left corner of the lower-left cell
  double origin_y = 0;
  bool negate = false;  ///< dark pixels free when true
  double occupied_thresh = 0;
  double free_thresh = 0;
  MapMode mode = MapMode::trinary;
};

/// Parses the YAML text of `path` (used for messages and to resolve `image`). Throws
/// sdk::Error(bad_world) naming the file and the key: a missing or mistyped key, resolution <= 0,
/// thresholds outside [0, 1] or free_thresh > occupied_thresh, an unknown mode, a yaw other
/// than 0 (a rotated map is not supported).
MapYaml parse_map_yaml(const std::string& text, const std::string& path);

const char* mode_name(MapMode mode);

}  // namespace flipper::plugins::ros_map
