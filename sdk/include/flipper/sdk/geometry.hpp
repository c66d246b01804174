#pragma once
/// @file geometry.hpp
/// Cells and areas: the only spatial vocabulary the core language needs. A cell is a small
/// integer vector (z = 0 in 2-D worlds); an area is a set of cells kept as a sorted, duplicate-free
/// vector, ordered by (x, y, z) — which is also the language's tie order ("smallest x, then y").

#include <compare>
#include <cstdint>
#include <string>
#include <vector>

// Before the Area below: GCC 12's -Wshadow takes the enumerator Sort::Area, when declared after
// it, for a shadowing declaration; in this order it does not (a unit, or a unity batch of the
// product's units, may include this header first).
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

struct Cell {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;
  friend constexpr auto operator<=>(const Cell&, const Cell&) = default;
  friend constexpr Cell operator+(Cell a, Cell b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
};

/// "[x,y]" for 2-D (dims == 2) or "[x,y,z]".
FLIPPER_SDK_API std::string to_string(const Cell& c, int dims = 2);

/// A set of cells: sorted by (x, y, z), no duplicates. Use the helpers to keep it so.
using Area = std::vector<Cell>;

namespace areas {
/// Sorts and removes duplicates in place.
FLIPPER_SDK_API void normalize(Area& a);
FLIPPER_SDK_API Area unite(const Area& a, const Area& b);
FLIPPER_SDK_API Area intersect(const Area& a, const Area& b);
FLIPPER_SDK_API Area subtract(const Area& a, const Area& b);
FLIPPER_SDK_API bool contains(const Area& a, const Cell& c);
}  // namespace areas

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
