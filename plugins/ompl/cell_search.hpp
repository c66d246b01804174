#pragma once
// Cell-graph helpers for the sampling planner: which cells a path may enter (free, not avoided,
// start exempt), which are reachable from the start, and short breadth-first repairs between two
// cells. Buffers are flat arrays over the geometry's box, allocated once per request and reused
// by every search through an epoch stamp (no clearing between searches).
#include <cstdint>
#include <vector>

#include "flipper/sdk/world.hpp"

namespace flipper::plugins::ompl {

class CellSearch {
 public:
  /// `avoid` may be null; `start` is always passable (the start cell is exempt).
  CellSearch(const sdk::Geometry& geometry, const sdk::Area* avoid, sdk::Cell start);

  const sdk::Geometry& geometry() const { return g_; }
  sdk::Cell start() const { return start_; }
  /// In the box, free, and not avoided (or the start).
  bool passable(sdk::Cell c) const { return g_.in_bounds(c) && pass_[g_.index(c)] != 0; }
  /// Connected to the start through passable cells (flood fill done on construction).
  bool reachable(sdk::Cell c) const { return g_.in_bounds(c) && reach_[g_.index(c)] != 0; }

  /// Breadth-first search from `from` to `to` through passable cells, neighbours expanded in the
  /// geometry's tie order, restricted to the bounding box of both cells grown by `margin` cells
  /// (margin < 0: the whole world). On success appends the cells entered (excluding `from`) to
  /// `out` and returns true.
  bool connect(sdk::Cell from, sdk::Cell to, int margin, std::vector<sdk::Cell>& out);

 private:
  const sdk::Geometry& g_;
  sdk::Cell start_;
  std::vector<std::uint8_t> pass_;
  std::vector<std::uint8_t> reach_;
  std::vector<std::uint32_t> seen_;  // == epoch_: visited in the current search
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> queue_;
  std::vector<std::int64_t> step_;  // index delta of each neighbour offset
  std::uint32_t epoch_ = 0;
};

/// Euclidean distance between cell centres.
double distance(sdk::Cell a, sdk::Cell b);

}  // namespace flipper::plugins::ompl
