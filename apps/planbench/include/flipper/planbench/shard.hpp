#pragma once
/// @file shard.hpp
/// A benchmark split over machines or processes, and joined again (docs/planners.md §5,
/// "Shards"). The unit is one plan: a task of a cell (world × planner × seed), one row of
/// runs.csv. Row r of the whole run's runs.csv (cells in order, each cell's tasks in order)
/// belongs to shard r mod N, so every plan is in exactly one shard and shards are balanced
/// across cells. `merge_bench` checks that runs are the N complete shards of one experiment and
/// assembles the whole run from their rows: the files of a run made in one piece, but for the
/// measured columns and figures.

#include <cstddef>
#include <string>
#include <vector>

#include "flipper/planbench/bench.hpp"
#include "flipper/record/sweep.hpp"

namespace flipper::planbench {

/// For each cell (with `tasks_per_cell[i]` tasks), the indices of its tasks that shard `s`
/// runs, in order: task t of cell i is row r = (tasks of the cells before i) + t, in the shard
/// when r mod N = I. Shard 0/1 has every task.
std::vector<std::vector<std::size_t>> shard_tasks(const std::vector<std::size_t>& tasks_per_cell,
                                                  const record::Shard& shard);

/// Merges the finished shard runs (`--shard I/N`) of one experiment into a new run under `out`
/// (`<stem>-merged-...`): refuses (sdk::Error(bad_request), naming the run) a folder that is no
/// finished planner benchmark shard, shards of different experiments, inputs, --set, tasks or
/// cells, a second shard I, a missing one, and a shard whose rows are not its share of the
/// grid. Differences of build or source are `warnings`. `latest` moves to the merged run.
BenchResult merge_bench(const std::vector<std::string>& runs, const std::string& out, bool plots,
                        std::vector<std::string>& warnings);

}  // namespace flipper::planbench
