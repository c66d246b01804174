#pragma once
/// @file sweep.hpp
/// Grids of settings and how a grid is split (docs/experiments.md §4). A sweep is an ordered list
/// of axes, each a config key with its values; the grid is their cartesian product, the last axis
/// varying fastest. A grid point is named by its assignments, `key=value` joined by commas in
/// axis order (`planner.plugin=ompl,planner.params.seed=2`): readable, and stable as long as the
/// sweep is. Seed axes (a key whose last part is `seed` or ends in `_seed`) are what a
/// condition's spread is taken over.

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace flipper::record {

struct SweepAxis {
  std::string key;
  std::vector<std::string> values;  ///< as `--set` text
};
using Assignment = std::pair<std::string, std::string>;  ///< key, value

/// Every grid point, in order. An empty sweep has one point with no assignments.
std::vector<std::vector<Assignment>> expand_grid(const std::vector<SweepAxis>& axes);
/// "k1=v1,k2=v2".
std::string point_name(const std::vector<Assignment>& point);
/// Whether a key names a seed (last part `seed`, or ending in `_seed`).
bool is_seed_key(const std::string& key);

/// One of N parts of a grid: `--shard I/N`, I from 0 to N-1 (a Slurm array's
/// SLURM_ARRAY_TASK_ID with --array=0-(N-1), a Kubernetes indexed job's JOB_COMPLETION_INDEX).
struct Shard {
  int index = 0, count = 1;
};
/// Parses "I/N". Throws sdk::Error(bad_request) for anything else or I outside 0..N-1.
Shard parse_shard(const std::string& text);
/// Variant `i` of a grid belongs to shard i mod N: every shard gets every N-th variant, so
/// shards of a grid ordered by key are balanced across keys.
inline bool in_shard(std::size_t i, const Shard& s) {
  return static_cast<int>(i % static_cast<std::size_t>(s.count)) == s.index;
}

}  // namespace flipper::record
