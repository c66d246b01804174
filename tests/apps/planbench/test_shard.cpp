// The benchmark's shards (docs/planners.md §5, "Shards"): row r of the whole run (cells in
// order, each cell's tasks in order) is in shard r mod N. Exact shares for small N by hand, and
// every row in exactly one shard for N = 1, 2, 3, the number of rows and one more.
#include <catch2/catch.hpp>
#include <map>
#include <utility>

#include "flipper/planbench/shard.hpp"

using namespace flipper;
using namespace flipper::planbench;
using Shares = std::vector<std::vector<std::size_t>>;

namespace {

// Cells of 5, 3, 0 and 2 tasks: 10 rows. Row numbers: cell 0 rows 0-4, cell 1 rows 5-7, cell 3
// rows 8-9 (cell 2 has none).
const std::vector<std::size_t> kTasks{5, 3, 0, 2};
constexpr std::size_t kRows = 10;

}  // namespace

TEST_CASE("shards: each shard's tasks per cell, counted by hand") {
  CHECK(shard_tasks(kTasks, {0, 1}) == Shares{{0, 1, 2, 3, 4}, {0, 1, 2}, {}, {0, 1}});
  // N = 2: even rows 0 2 4 | 6 | 8, odd rows 1 3 | 5 7 | 9.
  CHECK(shard_tasks(kTasks, {0, 2}) == Shares{{0, 2, 4}, {1}, {}, {0}});
  CHECK(shard_tasks(kTasks, {1, 2}) == Shares{{1, 3}, {0, 2}, {}, {1}});
  // N = 3: rows 0 3 6 9 | 1 4 7 | 2 5 8.
  CHECK(shard_tasks(kTasks, {0, 3}) == Shares{{0, 3}, {1}, {}, {1}});
  CHECK(shard_tasks(kTasks, {1, 3}) == Shares{{1, 4}, {2}, {}, {}});
  CHECK(shard_tasks(kTasks, {2, 3}) == Shares{{2}, {0}, {}, {0}});
  // N = rows: one row each; the last row (cell 3's second task) is shard 9's.
  CHECK(shard_tasks(kTasks, {9, 10}) == Shares{{}, {}, {}, {1}});
  CHECK(shard_tasks(kTasks, {5, 10}) == Shares{{}, {0}, {}, {}});
  // N = rows + 1: the last shard has nothing to do.
  CHECK(shard_tasks(kTasks, {10, 11}) == Shares{{}, {}, {}, {}});
  // No cells: nothing anywhere.
  CHECK(shard_tasks({}, {0, 2}).empty());
}

TEST_CASE("shards: every row is in exactly one shard, for N = 1, 2, 3, rows and rows + 1") {
  for (const int n : {1, 2, 3, static_cast<int>(kRows), static_cast<int>(kRows) + 1}) {
    CAPTURE(n);
    std::map<std::pair<std::size_t, std::size_t>, int> seen;  // (cell, task) -> shards
    std::size_t largest = 0, smallest = kRows;
    for (int i = 0; i < n; ++i) {
      const Shares shares = shard_tasks(kTasks, {i, n});
      REQUIRE(shares.size() == kTasks.size());
      std::size_t mine = 0;
      for (std::size_t c = 0; c < shares.size(); ++c)
        for (const std::size_t t : shares[c]) {
          REQUIRE(t < kTasks[c]);
          ++seen[{c, t}];
          ++mine;
        }
      largest = std::max(largest, mine);
      smallest = std::min(smallest, mine);
    }
    CHECK(seen.size() == kRows);
    for (const auto& [where, count] : seen) CHECK(count == 1);
    // Balanced: the shares differ by at most one row.
    CHECK(largest - smallest <= 1);
  }
}
