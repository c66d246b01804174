#pragma once
/// @file occupancy.hpp
/// From grey pixels to occupancy values exactly as Nav2's map_server does (map_io.cpp,
/// loadMapFromFile), and from occupancy values to the cells a planner may use
/// (docs/ros-maps.md, "Cells").
#include <cstdint>
#include <vector>

#include "map_yaml.hpp"
#include "pgm.hpp"

namespace flipper::plugins::ros_map {

inline constexpr std::int8_t kUnknown = -1;
inline constexpr std::int8_t kFree = 0;
inline constexpr std::int8_t kOccupied = 100;

/// One pixel's occupancy value: 0..100 or -1 (unknown), as nav_msgs/OccupancyGrid holds it.
/// shade = value / maxval; occ = shade if negate, else 1 - shade (in double arithmetic, as Nav2
/// computes it). trinary: occupied_thresh < occ -> 100, occ < free_thresh -> 0, else -1;
/// scale: as trinary, but between the thresholds rint((occ - free) / (occupied - free) * 100);
/// raw: round(shade * 255) if it lies in 0..100, else -1 (negate and thresholds ignored).
std::int8_t occupancy_of(std::uint32_t value, std::uint32_t maxval, const MapYaml& map);

/// The grid in map order: cell (x, y) is image column x, row height - 1 - y (row 0 of the
/// image is the top of the map); index x + width * y.
struct OccupancyGrid {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::int8_t> values;
  std::int8_t at(std::uint32_t x, std::uint32_t y) const {
    return values[static_cast<std::size_t>(y) * width + x];
  }
};

OccupancyGrid occupancy_grid(const GreyImage& image, const MapYaml& map);

/// What the planners may use: a cell is blocked if unknown (-1) or at least `lethal` (Nav2's
/// static layer: lethal_cost_threshold), and so is every cell whose centre lies within
/// `radius_cells` of a blocked-by-value cell's centre (the inscribed radius of the robot; with
/// `inflate_unknown`, unknown cells inflate too). One byte per cell, non-zero = free, x fastest.
std::vector<std::uint8_t> free_mask(const OccupancyGrid& grid, int lethal, double radius_cells,
                                    bool inflate_unknown);

}  // namespace flipper::plugins::ros_map
