#pragma once
/// @file inflation.hpp
/// The exact Euclidean distance transform of Felzenszwalb and Huttenlocher ("Distance
/// Transforms of Sampled Functions", 2012): for every cell, the squared distance (in cells,
/// centre to centre) to the nearest source cell, in O(cells) whatever the inflation radius.
#include <cstdint>
#include <vector>

namespace flipper::plugins::ros_map {

/// `sources`: width * height bytes, x fastest, non-zero = source. Cells with no source at all
/// get +infinity.
std::vector<double> squared_distances(const std::vector<std::uint8_t>& sources, std::uint32_t width,
                                      std::uint32_t height);

}  // namespace flipper::plugins::ros_map
