#include "flipper/sdk/geometry.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

std::string to_string(const Cell& c, int dims) {
  std::string s = "[" + std::to_string(c.x) + "," + std::to_string(c.y);
  if (dims == 3) s += "," + std::to_string(c.z);
  return s + "]";
}

namespace areas {
void normalize(Area& a) {
  // Lists written by write_world (and so most a client sends back) are sorted already.
  if (!std::is_sorted(a.begin(), a.end())) std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
}
Area unite(const Area& a, const Area& b) {
  Area out;
  out.reserve(a.size() + b.size());
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}
Area intersect(const Area& a, const Area& b) {
  Area out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}
Area subtract(const Area& a, const Area& b) {
  Area out;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}
bool contains(const Area& a, const Cell& c) {
  return std::binary_search(a.begin(), a.end(), c);
}
}  // namespace areas

Geometry::Geometry(int dims, Cell min, Cell max, std::vector<std::uint8_t> free_mask,
                   std::vector<Cell> neighbour_offsets,
                   std::vector<std::pair<std::string, Cell>> directions,
                   std::shared_ptr<const ContinuousSpace> continuous)
    : dims_(dims),
      min_(min),
      max_(max),
      free_(std::move(free_mask)),
      neighbours_(std::move(neighbour_offsets)),
      directions_(std::move(directions)),
      continuous_(std::move(continuous)) {
  if (dims != 2 && dims != 3) throw Error(codes::kBadWorld, "geometry: dims must be 2 or 3");
  if (max.x < min.x || max.y < min.y || max.z < min.z)
    throw Error(codes::kBadWorld, "geometry: empty bounds");
  // Extents in 64 bits: max - min + 1 overflows int for bounds that span most of its range.
  const auto extent = [](int lo, int hi) {
    return static_cast<std::size_t>(static_cast<std::int64_t>(hi) - lo + 1);
  };
  sx_ = extent(min.x, max.x);
  sy_ = extent(min.y, max.y);
  sz_ = extent(min.z, max.z);
  std::size_t cells = 0;
  if (__builtin_mul_overflow(sx_, sy_, &cells) || __builtin_mul_overflow(cells, sz_, &cells) ||
      free_.size() != cells)
    throw Error(codes::kBadWorld, "geometry: free mask size does not match the bounds");
  // Counted first: one allocation of the exact size, not a doubling vector's copies.
  free_cells_.reserve(static_cast<std::size_t>(
      std::count_if(free_.begin(), free_.end(), [](std::uint8_t f) { return f != 0; })));
  // Cells in (x, y, z) order: iterate x outermost so the result is sorted without a sort.
  // 64-bit counters: `x <= max.x; ++x` never ends (and overflows) when max.x is INT_MAX.
  for (std::int64_t x = min.x; x <= max.x; ++x)
    for (std::int64_t y = min.y; y <= max.y; ++y)
      for (std::int64_t z = min.z; z <= max.z; ++z) {
        const Cell c{static_cast<std::int32_t>(x), static_cast<std::int32_t>(y),
                     static_cast<std::int32_t>(z)};
        if (free_[index(c)]) free_cells_.push_back(c);
      }
}

Geometry::~Geometry() = default;

Cell Geometry::cell_at(std::size_t i) const {
  Cell c;
  c.x = min_.x + static_cast<std::int32_t>(i % sx_);
  i /= sx_;
  c.y = min_.y + static_cast<std::int32_t>(i % sy_);
  i /= sy_;
  c.z = min_.z + static_cast<std::int32_t>(i);
  return c;
}

std::optional<Cell> Geometry::direction(std::string_view word) const {
  for (const auto& [w, off] : directions_)
    if (w == word) return off;
  return std::nullopt;
}

bool WorldState::same_state(const WorldState& o) const {
  if (robot != o.robot || items != o.items || held != o.held) return false;
  if (geometry != o.geometry) return false;
  if (rooms != o.rooms && !(rooms && o.rooms && *rooms == *o.rooms)) return false;
  return true;
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
