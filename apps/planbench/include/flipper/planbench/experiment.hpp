#pragma once
/// @file experiment.hpp
/// A planner benchmark's experiment file (docs/planners.md §5): the worlds, the planners (any
/// plugin by name: in-tree, or out-of-tree through `plugin_paths`), the seeds given to planners
/// that declare a `seed` param, and the tasks of each world (random from a seed, or a task file).
/// Paths written in the file resolve against its directory.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace flipper::planbench {

/// Where a world's tasks come from: `random` tasks drawn with `seed`, or a task file.
struct TaskSource {
  int random = 0;          ///< how many random (start, goal) pairs the oracle connects
  std::uint64_t seed = 1;  ///< the stream they are drawn from
  std::string file;        ///< a task file (absolute), instead of random tasks
};

struct WorldSpec {
  std::string name;                 ///< a label (runs.csv `world`)
  std::string plugin;               ///< world plugin
  std::string file;                 ///< world file (absolute)
  std::string params;               ///< the plugin's params as YAML flow text ("" : its defaults)
  std::optional<TaskSource> tasks;  ///< this world's own tasks (default: the experiment's)
};

struct PlannerSpec {
  std::string name;    ///< a label (runs.csv `planner`), default: the plugin name
  std::string plugin;  ///< planner plugin
  std::string params;  ///< its params as YAML flow text ("" : its defaults)
};

struct BenchExperiment {
  std::string file;  ///< the experiment file (absolute), "" when built in code
  std::string name;
  std::string config;                     ///< base flipper config ("" : the embedded default)
  std::vector<std::string> sets;          ///< `set:` applied to every cell
  std::vector<std::string> plugin_paths;  ///< absolute; become `plugin_paths=[...]`
  std::vector<std::uint64_t> seeds{1};    ///< for planners that declare `seed`
  int repetitions = 1;                    ///< plans per task (CPU time: their median)
  /// One plan's time limits (docs/planners.md §2): the planning thread's CPU time, and a far
  /// wall-clock backstop against hangs (not load); either makes the row `stopped`.
  std::int64_t cpu_budget_ms = 10000;
  std::int64_t deadline_ms = 600000;
  /// The last resort against a planner that ignores its stop condition: a cell's process still
  /// planning one task after this many seconds is killed, and the task's row says
  /// `wall_backstop` (docs/planners.md §5). Past deadline_ms, so a plan that honours its stop
  /// condition is stopped by it first.
  int kill_after_s = 900;
  TaskSource tasks{20, 1, ""};
  std::vector<WorldSpec> worlds;
  std::vector<PlannerSpec> planners;
};

/// Reads and checks an experiment file. Throws sdk::Error(bad_config) naming the file and key.
BenchExperiment load_bench_experiment(const std::string& path);

/// The experiment as the manifest records it.
nlohmann::json experiment_json(const BenchExperiment& e);

}  // namespace flipper::planbench
