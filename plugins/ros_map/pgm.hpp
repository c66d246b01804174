#pragma once
/// @file pgm.hpp
/// Netpbm grey images (PGM), the image format of ROS map_server maps: binary P5 and plain P2,
/// 8-bit (maxval <= 255) or 16-bit (maxval <= 65535, big-endian in P5). Width and height are
/// checked against a cell limit before any pixel is stored (docs/ros-maps.md, "Bounds").
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace flipper::plugins::ros_map {

/// A grey image, row 0 at the top (as in the file).
struct GreyImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t maxval = 255;
  std::vector<std::uint16_t> pixels;  ///< width * height, row-major from the top row
  std::uint16_t at(std::uint32_t column, std::uint32_t row) const {
    return pixels[static_cast<std::size_t>(row) * width + column];
  }
};

/// Decodes PGM bytes. `name` (the file) starts every error message; more than `max_cells`
/// pixels is refused from the header alone. Throws sdk::Error(bad_world): wrong magic, a bad
/// header field, maxval 0 or above 65535, a truncated pixel array, a pixel above maxval,
/// world_too_large for too many pixels.
/// `limit_name` names the limit in that refusal (this plugin's param or the host's key).
GreyImage decode_pgm(std::string_view bytes, const std::string& name, std::uint64_t max_cells,
                     const char* limit_name = "max_cells");

}  // namespace flipper::plugins::ros_map
