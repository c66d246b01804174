#pragma once
/// @file tasks.hpp
/// Benchmark tasks (docs/planners.md §5): a start and a goal cell on one world, with the
/// oracle's shortest path length: a breadth-first search over the world's free cells and its
/// neighbourhood, independent of every planner plugin. Tasks are drawn at random from a seed
/// (SplitMix64, the same tasks on every machine) or read from a task file.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "flipper/planbench/experiment.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::planbench {

struct Task {
  std::string name;  ///< "t1", ... or the task file's name
  sdk::Cell start, goal;
  std::optional<std::size_t> shortest;  ///< the oracle's steps; none when unreachable
};

/// Steps of a shortest path from `start` to `goal` over free cells (breadth-first, the
/// geometry's neighbourhood), or none when `goal` cannot be reached.
std::optional<std::size_t> shortest_steps(const sdk::Geometry& g, sdk::Cell start, sdk::Cell goal);

/// The next value of a SplitMix64 stream (Steele, Lea and Flood 2014; `state` advances): the
/// same numbers on every platform and standard library.
std::uint64_t splitmix64(std::uint64_t& state);

/// `count` tasks of distinct free start and goal cells that the oracle connects, drawn from the
/// SplitMix64 stream of `seed` (cell = next() mod the number of free cells). Gives up after
/// 1000 × count draws (a world whose free cells are mostly cut off): fewer tasks then.
std::vector<Task> random_tasks(const sdk::Geometry& g, int count, std::uint64_t seed);

/// A task file: `tasks: [{name, start: [x, y(, z)], goal: [x, y(, z)]}, ...]` (name optional).
/// Cells must be free cells of the world. Throws sdk::Error(bad_config) naming the file and task.
std::vector<Task> read_task_file(const std::string& path, const sdk::Geometry& g);

/// The tasks a source names on a world.
std::vector<Task> tasks_for(const TaskSource& source, const sdk::Geometry& g);

}  // namespace flipper::planbench
