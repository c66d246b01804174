#include "occupancy.hpp"

#include <cmath>

#include "inflation.hpp"

namespace flipper::plugins::ros_map {

std::int8_t occupancy_of(std::uint32_t value, std::uint32_t maxval, const MapYaml& map) {
  // Nav2: shade = scaleQuantumToDouble(quantum), which for an 8-bit image is value / 255.
  const double shade = static_cast<double>(value) / static_cast<double>(maxval);
  const double occ = map.negate ? shade : 1.0 - shade;
  switch (map.mode) {
    case MapMode::trinary:
      if (map.occupied_thresh < occ) return kOccupied;
      if (occ < map.free_thresh) return kFree;
      return kUnknown;
    case MapMode::scale:
      if (map.occupied_thresh < occ) return kOccupied;
      if (occ < map.free_thresh) return kFree;
      return static_cast<std::int8_t>(
          std::rint((occ - map.free_thresh) / (map.occupied_thresh - map.free_thresh) * 100.0));
    case MapMode::raw: {
      const double percent = std::round(shade * 255);
      if (percent >= 0 && percent <= 100) return static_cast<std::int8_t>(percent);
      return kUnknown;
    }
  }
  return kUnknown;
}

OccupancyGrid occupancy_grid(const GreyImage& image, const MapYaml& map) {
  OccupancyGrid g;
  g.width = image.width;
  g.height = image.height;
  g.values.resize(static_cast<std::size_t>(image.width) * image.height);
  // A lookup table: at most 65536 values, computed once each.
  std::vector<std::int8_t> table(static_cast<std::size_t>(image.maxval) + 1);
  for (std::uint32_t v = 0; v <= image.maxval; ++v) table[v] = occupancy_of(v, image.maxval, map);
  for (std::uint32_t row = 0; row < image.height; ++row) {
    const std::uint32_t y = image.height - 1 - row;
    for (std::uint32_t x = 0; x < image.width; ++x)
      g.values[static_cast<std::size_t>(y) * g.width + x] = table[image.at(x, row)];
  }
  return g;
}

std::vector<std::uint8_t> free_mask(const OccupancyGrid& grid, int lethal, double radius_cells,
                                    bool inflate_unknown) {
  const std::size_t n = grid.values.size();
  std::vector<std::uint8_t> mask(n);
  std::vector<std::uint8_t> sources(n);
  bool any_source = false;
  for (std::size_t i = 0; i < n; ++i) {
    const int v = grid.values[i];
    const bool lethal_value = v >= lethal;
    const bool unknown = v == kUnknown;
    mask[i] = (lethal_value || unknown) ? 0 : 1;
    sources[i] = (lethal_value || (inflate_unknown && unknown)) ? 1 : 0;
    any_source = any_source || sources[i] != 0;
  }
  if (radius_cells <= 0 || !any_source) return mask;
  const std::vector<double> d2 = squared_distances(sources, grid.width, grid.height);
  // A tolerance of 1e-9 cell^2: a radius of exactly k cells blocks the cells k cells away even
  // when radius / resolution is computed a hair below k.
  const double r2 = radius_cells * radius_cells + 1e-9;
  for (std::size_t i = 0; i < n; ++i)
    if (d2[i] <= r2) mask[i] = 0;
  return mask;
}

}  // namespace flipper::plugins::ros_map
