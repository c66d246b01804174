#pragma once
/// @file bench.hpp
/// Running a planner benchmark into a run folder (docs/planners.md §5): every plugin is loaded
/// and checked first (a missing plugin, a plugin of another kind, a bad param or world fail
/// before anything runs, as sdk::Error), the tasks are drawn, then each cell (world × planner ×
/// seed) runs in its own process, at most `jobs` at once (apps/record processes.hpp); the rows
/// are joined in cell order, so runs.csv does not depend on `jobs` but for measured columns.
/// A cell's process that dies (a plugin's crash, a hang stopped by the `kill_after_s` backstop)
/// costs the task it was on: that task's row names the cause, the cell's later tasks run in a
/// new process, and the manifest says `status: partial` (or `failed`) with the failed tasks.
/// `latest` moves to the run once its manifest is written.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipper/planbench/experiment.hpp"
#include "flipper/record/plots.hpp"
#include "flipper/record/sweep.hpp"

namespace flipper::planbench {

struct BenchOptions {
  std::string config;                  ///< --config ("" : the experiment's, or the default)
  std::vector<std::string> overrides;  ///< --set, applied to every cell after the experiment's
  std::string out;                     ///< parent of the run folder
  int jobs = 1;
  bool plots = true;
  /// A run folder to resume (`bench planners resume`): its cells' rows are kept, each cell goes
  /// on from its first task without a row. "" : a new run under `out`.
  std::string resume;
  /// Run only this shard's plans (`--shard I/N`, shard.hpp); the run folder is
  /// `<stem>-shardIofN-...` and its manifest records `shard`. None: the whole grid.
  std::optional<record::Shard> shard;
  /// Called as cells finish (done, total); a cell that lost a task counts when its last process
  /// ends. Nothing when unset.
  std::function<void(std::size_t, std::size_t)> progress;
};

struct BenchResult {
  std::string run_dir;
  record::PlotOutcome plots;
  std::size_t cells = 0, runs = 0;
  std::size_t failures = 0;  ///< tasks whose process died (crash, backstop)
  std::string status;        ///< the manifest's: complete, partial or failed
};

BenchResult run_bench(const BenchExperiment& e, const BenchOptions& options);

/// Resumes an interrupted run (manifest `status: running`, written when it started): the
/// experiment file, worlds and task files must have the checksums the manifest recorded (else
/// sdk::Error(bad_request) naming the file); its --config and --set are the recorded ones.
BenchResult resume_bench(const std::string& run_dir, int jobs, bool plots);

/// A re-run of a finished run compared with it.
struct BenchCheck {
  std::string text;                         ///< the comparison (record/compare.hpp), Markdown
  std::size_t compared = 0, differing = 0;  ///< deterministic figures (timing ones never count)
  std::string rerun;                        ///< the re-run's folder when kept, else ""
};
/// Re-runs a finished run from its manifest (inputs checksummed as for resume, its --config and
/// --set) into a new run under `keep_under` (or a temporary folder, removed), and compares every
/// deterministic figure (docs/planners.md §5).
BenchCheck check_bench(const std::string& run_dir, int jobs, const std::string& keep_under);

}  // namespace flipper::planbench
