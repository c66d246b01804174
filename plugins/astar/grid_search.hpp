#pragma once
// Breadth-first search over a Geometry's free cells, on flat arrays reused between calls.
// One byte per cell holds everything the search reads in its inner loop: blocked / free /
// visited-from-direction-k, plus goal and target flags. The free mask is copied into a grid
// padded with blocked cells, so neighbour steps are plain index offsets with no bounds checks,
// and parents are recovered from the stored direction. Not thread-safe: one GridSearch serves
// one call at a time (the planner serialises calls).
#include <cstdint>
#include <string>
#include <vector>

#include "flipper/sdk/planner.hpp"

namespace flipper::plugins::astar {

class GridSearch {
 public:
  /// Copies `g`'s free mask into the padded grid (every free cell passable). False if the
  /// padded grid would not fit 32-bit indexes or the neighbourhood has more than 6 offsets.
  bool prepare(const sdk::Geometry& g);
  /// Makes the cells of `avoid` impassable, except `exempt` (the start cell).
  void block(const sdk::Area& avoid, sdk::Cell exempt);

  /// Whether `c` lies inside the geometry's box.
  bool in_box(sdk::Cell c) const {
    return c.x >= min_.x && c.y >= min_.y && c.z >= min_.z && c.x <= max_.x && c.y <= max_.y &&
           c.z <= max_.z;
  }
  std::uint32_t index(sdk::Cell c) const {
    return static_cast<std::uint32_t>(
        (c.x - min_.x + pad_.x) +
        px_ * ((c.y - min_.y + pad_.y) + py_ * static_cast<std::int64_t>(c.z - min_.z + pad_.z)));
  }
  sdk::Cell cell(std::uint32_t i) const;

  /// Whether a path search has used the grid since prepare() (then prepare() again first).
  bool dirty() const { return dirty_; }

  /// Shortest path from `start` (in the box) to the nearest free cell of `goals` (ties:
  /// smallest cell), following BFS parents with neighbours in offset order.
  sdk::PathResult shortest_path(sdk::Cell start, const sdk::Area& goals,
                                const sdk::StopCondition& stop, std::uint64_t budget);

  /// As shortest_path, but for a single goal cell, searched by A* with the Manhattan distance
  /// as heuristic: the path is as short, but where several shortest paths exist it may differ
  /// from the breadth-first one (the tie rule of core-language §8 does not hold).
  sdk::PathResult shortest_path_astar(sdk::Cell start, sdk::Cell goal,
                                      const sdk::StopCondition& stop, std::uint64_t budget);

  /// Greedy tours: flags `cells` (in the box) as goals for nearest_goal().
  void set_goals(const std::vector<sdk::Cell>& cells);
  void unset_goal(sdk::Cell c);
  /// BFS from `from` to the nearest flagged goal (ties: smallest cell), leaving the grid as it
  /// was (flags included). Returns the distance, or -1 if no goal is reachable or `stop` fired
  /// (then `stopped` is set).
  std::int32_t nearest_goal(sdk::Cell from, sdk::Cell& goal, const sdk::StopCondition& stop,
                            std::uint64_t budget, std::uint64_t& expansions, bool& stopped);

  /// Tour support: marks `cells` (in the box) as targets 0..n-1.
  void set_targets(const std::vector<sdk::Cell>& cells);
  void clear_targets();
  /// BFS from `from`, which is target `source` (or no target when source < 0); writes the
  /// distance to every target reached into row[target] (others left untouched) and stops once
  /// every target with an id greater than `source` has been reached. False if `stop` fired.
  bool distances(sdk::Cell from, int source, std::int32_t* row, const sdk::StopCondition& stop,
                 std::uint64_t budget, std::uint64_t& expansions);

 private:
  // Cell state bits. The low three bits: 0 blocked, 1 free and not yet reached, 2 + k reached
  // through neighbour offset k.
  static constexpr std::uint8_t kBlocked = 0, kOpen = 1, kReachedBase = 2, kStateMask = 7;
  static constexpr std::uint8_t kGoal = 8, kTarget = 16, kClosed = 32;

  bool should_stop(std::uint64_t expansions, const sdk::StopCondition& stop,
                   std::uint64_t budget) const {
    // The clock and the cancel flag are polled every 1024 expansions; budgets are exact.
    return expansions >= budget || expansions >= stop.max_expansions ||
           ((expansions & 1023u) == 0 && stop.should_stop(expansions));
  }
  /// Puts every cell the last search reached back to kOpen (cheaper than a fresh copy).
  void reset_reached();
  /// The cell a search reached `v` from (v must have been reached, and not be the root).
  std::uint32_t parent(std::uint32_t v) const {
    return static_cast<std::uint32_t>(static_cast<std::int64_t>(v) -
                                      deltas_[(state_[v] & kStateMask) - kReachedBase]);
  }
  /// The cells from `root` (excluded) to `v` (included), following parents.
  void trace_path(std::uint32_t v, std::uint32_t root, std::vector<sdk::Cell>& path) const;

  // The search loops, specialised on the neighbour count (K = 0: any count).
  template <int K>
  bool bfs_to_goals(std::uint32_t s, const sdk::StopCondition& stop, std::uint64_t budget,
                    std::uint32_t& best, bool& found, std::uint64_t& expansions);
  template <int K>
  bool bfs_distances(std::uint32_t s, int source, std::size_t wanted, std::int32_t* row,
                     const sdk::StopCondition& stop, std::uint64_t budget,
                     std::uint64_t& expansions);
  /// Calls `search(std::integral_constant<int, K>)` with K = this grid's neighbour count when a
  /// loop is specialised for it, else K = 0.
  template <class Search>
  bool for_neighbour_count(Search&& search) const;

  sdk::Cell min_{}, max_{};
  sdk::Cell pad_{};
  std::int64_t px_ = 0, py_ = 0, pz_ = 0;
  std::vector<std::int64_t> deltas_;
  std::vector<std::uint8_t> state_;
  std::vector<std::uint32_t> goal_cells_;    // cells flagged kGoal
  std::vector<std::uint32_t> target_cells_;  // cells flagged kTarget, by target id
  std::vector<std::uint32_t> queue_;         // one slot per cell; [0, queue_len_) = cells reached
  std::size_t queue_len_ = 0;
  bool dirty_ = true;  // a path search left marks behind: prepare() before the next search
  std::vector<std::int32_t> target_id_;              // valid where kTarget is set
  std::vector<std::uint32_t> g_;                     // A*: path length, valid where reached
  std::vector<std::vector<std::uint32_t>> buckets_;  // A*: open cells by f - f(start)
};

}  // namespace flipper::plugins::astar
