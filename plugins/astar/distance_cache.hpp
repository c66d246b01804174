#pragma once
// Path distances between cells of one static geometry, remembered across tours. A session keeps
// its map while items move, so the same point cells come back query after query; on a 1024^2
// map each breadth-first row of a tour's distance matrix costs up to a million cells.
// Distances are exact values of the geometry, so a hit changes no tour. Only symmetric
// neighbourhoods (d(a, b) == d(b, a)) are cached; the geometry is recognised by its box,
// neighbourhood and free mask (a copy, compared in full), and any other starts the cache afresh.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "flipper/sdk/world.hpp"

namespace flipper::plugins::astar {

class DistanceCache {
 public:
  /// Switches to `g`: keeps the entries if it is the geometry of the last call, else drops
  /// them. Returns whether the cache may be used for `g` (symmetric neighbourhood).
  bool use(const sdk::Geometry& g);

  /// The cached distance between two cells (-1: unreachable); false if not cached.
  bool find(sdk::Cell a, sdk::Cell b, std::int32_t& d) const;
  /// Remembers a distance (-1: unreachable). Past kMaxEntries the cache starts afresh.
  void store(sdk::Cell a, sdk::Cell b, std::int32_t d);
  /// Whether a tour over `n` vertices fits (its n(n-1)/2 pairs plus the start's row).
  static bool fits(std::size_t n) { return n * n / 2 + n <= kMaxEntries / 2; }

  static constexpr std::size_t kMaxEntries = 1u << 16;  // ~4 MiB at most

 private:
  std::uint64_t key(sdk::Cell a, sdk::Cell b) const;

  bool symmetric_ = false;
  int dims_ = 0;
  sdk::Cell min_{}, max_{};
  std::vector<sdk::Cell> offsets_;
  std::vector<std::uint8_t> mask_;
  std::uint64_t sx_ = 0, sy_ = 0;
  std::unordered_map<std::uint64_t, std::int32_t> distances_;
};

}  // namespace flipper::plugins::astar
