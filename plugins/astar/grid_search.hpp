#pragma once
// Breadth-first search over a Geometry's free cells, on flat arrays that are reused between calls.
// The free mask is copied into a grid padded with blocked cells, so neighbour steps are plain
// index offsets with no bounds checks; visited marks are generation stamps, so nothing is cleared
// between searches. Not thread-safe: one GridSearch serves one call at a time.
#include <cstdint>
#include <string>
#include <vector>

#include "flipper/sdk/planner.hpp"

namespace flipper::plugins::astar {

class GridSearch {
 public:
  /// Copies `g`'s free mask into the padded grid (every free cell passable). False if the
  /// padded grid would not fit 32-bit indexes.
  bool prepare(const sdk::Geometry& g);
  /// Makes the cells of `avoid` impassable, except `exempt` (the start cell).
  void block(const sdk::Area& avoid, sdk::Cell exempt);

  std::uint32_t index(sdk::Cell c) const {
    return static_cast<std::uint32_t>(
        (c.x - min_.x + pad_.x) +
        px_ * ((c.y - min_.y + pad_.y) + py_ * static_cast<std::int64_t>(c.z - min_.z + pad_.z)));
  }
  sdk::Cell cell(std::uint32_t i) const;

  /// Shortest path from `start` (in bounds) to the nearest free cell of `goals` (ties: smallest
  /// cell), following BFS parents with neighbours in offset order.
  sdk::PathResult shortest_path(sdk::Cell start, const sdk::Area& goals,
                                const sdk::StopCondition& stop, std::uint64_t budget);

  /// Tour support: marks `cells` as targets 0..n-1 (cells must be in bounds).
  void set_targets(const std::vector<sdk::Cell>& cells);
  void clear_targets();
  /// BFS from target `source` (or from `from` when source < 0); writes the distance to every
  /// target reached into row[target] (others left untouched) and stops once every target with an
  /// id greater than `source` has been reached. Returns false if `stop` fired.
  bool distances(sdk::Cell from, int source, std::int32_t* row, const sdk::StopCondition& stop,
                 std::uint64_t budget, std::uint64_t& expansions);

 private:
  bool should_stop(std::uint64_t expansions, const sdk::StopCondition& stop,
                   std::uint64_t budget) const {
    // The clock and the cancel flag are polled every 1024 expansions; budgets are exact.
    return expansions >= budget || expansions >= stop.max_expansions ||
           ((expansions & 1023u) == 0 && stop.should_stop(expansions));
  }
  std::uint32_t next_generation();

  sdk::Cell min_{};
  sdk::Cell pad_{};
  std::int64_t px_ = 0, py_ = 0, pz_ = 0;
  std::vector<std::int64_t> deltas_;
  std::vector<std::uint8_t> passable_;
  std::vector<std::uint32_t> seen_;  // == generation_ when visited in the current search
  std::uint32_t generation_ = 0;
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint8_t> goal_;
  std::vector<std::int32_t> target_;       // target id per cell, -1 if none
  std::vector<std::uint32_t> goal_cells_;  // cells set in goal_, to reset them cheaply
  std::vector<std::uint32_t> marked_;      // cells set in target_
  std::vector<std::uint32_t> queue_;
};

}  // namespace flipper::plugins::astar
