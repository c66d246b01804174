#pragma once
// A world's point lists read from its text without the JSON tree (world_format.cpp). The walls
// and rooms are most of a world's bytes, and nlohmann's lexer (a token string per value, strtoull
// per number) and tree spent about two thirds of a `world` op on them.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipper/sdk/geometry.hpp"

namespace flipper::sdk::detail {

/// The largest coordinate magnitude a world may use: headroom so that box sizes and neighbour
/// steps cannot overflow 32 bits. Every reader of world points checks against it.
inline constexpr std::int64_t kMaxCoordinate = std::int64_t{1} << 28;

/// The values of the top-level "walls" and "rooms" members, where they are plain, read from the
/// text, and where they are in it.
struct PointLists {
  struct Span {
    std::size_t begin = 0, end = 0;  ///< the value's bytes: [begin, end)
  };
  std::optional<std::vector<Cell>> walls;  ///< when "walls" is plain
  Span walls_at;
  /// When "rooms" is plain: (name, points) by name, as a JSON object's members are ordered.
  std::optional<std::vector<std::pair<std::string, std::vector<Cell>>>> rooms;
  Span rooms_at;
};

/// Plain means: "walls" a list of points, "rooms" an object of such lists under distinct,
/// non-empty names of printable ASCII without escapes; a point `dims` integers (no fraction or
/// exponent) within ±2^28, the range world_format accepts. A member that is not plain is left in
/// the text. Nullopt when neither is plain, a key occurs twice or has an escape (it might spell
/// either), or the text cannot be followed. Outside the values it takes, it checks only what it
/// needs to find them: the caller parses the rest with `[]` and `{}` in their place, and parses
/// the text as sent whenever that fails, so answers and error messages are the full parse's.
std::optional<PointLists> scan_point_lists(std::string_view text, int dims);

}  // namespace flipper::sdk::detail
