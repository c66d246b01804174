#include "distance_cache.hpp"

#include <algorithm>

namespace flipper::plugins::astar {
namespace {

bool symmetric(const std::vector<sdk::Cell>& offsets) {
  return std::all_of(offsets.begin(), offsets.end(), [&](const sdk::Cell& o) {
    return std::find(offsets.begin(), offsets.end(), sdk::Cell{-o.x, -o.y, -o.z}) != offsets.end();
  });
}

}  // namespace

bool DistanceCache::use(const sdk::Geometry& g) {
  // Compared in full (a memcmp of the mask is cheap next to one breadth-first row): a session
  // may hand over equal geometries at different addresses, and a stale hit would be wrong.
  const bool same = dims_ == g.dims() && min_ == g.min() && max_ == g.max() &&
                    offsets_ == g.neighbour_offsets() && mask_ == g.free_mask();
  if (!same) {
    distances_.clear();
    dims_ = g.dims();
    min_ = g.min();
    max_ = g.max();
    offsets_ = g.neighbour_offsets();
    mask_ = g.free_mask();
    symmetric_ = symmetric(offsets_);
    sx_ = g.size_x();
    sy_ = g.size_y();
  }
  return symmetric_;
}

std::uint64_t DistanceCache::key(sdk::Cell a, sdk::Cell b) const {
  if (b < a) std::swap(a, b);  // symmetric: one entry per pair
  auto index = [&](sdk::Cell c) {
    return static_cast<std::uint64_t>(c.x - min_.x) +
           sx_ * (static_cast<std::uint64_t>(c.y - min_.y) +
                  sy_ * static_cast<std::uint64_t>(c.z - min_.z));
  };
  return (index(a) << 32) | index(b);  // the tour checked that indexes fit 32 bits
}

bool DistanceCache::find(sdk::Cell a, sdk::Cell b, std::int32_t& d) const {
  const auto it = distances_.find(key(a, b));
  if (it == distances_.end()) return false;
  d = it->second;
  return true;
}

void DistanceCache::store(sdk::Cell a, sdk::Cell b, std::int32_t d) {
  if (distances_.size() >= kMaxEntries) distances_.clear();
  distances_[key(a, b)] = d;
}

}  // namespace flipper::plugins::astar
