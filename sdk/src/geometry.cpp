#include "flipper/sdk/geometry.hpp"

#include <algorithm>
#include <iterator>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace v1 {

std::string to_string(const Cell& c, int dims) {
  std::string s = "[" + std::to_string(c.x) + "," + std::to_string(c.y);
  if (dims == 3) s += "," + std::to_string(c.z);
  return s + "]";
}

namespace areas {
void normalize(Area& a) {
  std::sort(a.begin(), a.end());
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
  sx_ = static_cast<std::size_t>(max.x - min.x + 1);
  sy_ = static_cast<std::size_t>(max.y - min.y + 1);
  sz_ = static_cast<std::size_t>(max.z - min.z + 1);
  if (free_.size() != sx_ * sy_ * sz_)
    throw Error(codes::kBadWorld, "geometry: free mask size does not match the bounds");
  // Cells in (x, y, z) order: iterate x outermost so the result is sorted without a sort.
  for (std::int32_t x = min.x; x <= max.x; ++x)
    for (std::int32_t y = min.y; y <= max.y; ++y)
      for (std::int32_t z = min.z; z <= max.z; ++z) {
        Cell c{x, y, z};
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

}  // namespace v1
}  // namespace flipper::sdk
