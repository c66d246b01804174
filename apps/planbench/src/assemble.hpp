#pragma once
// A benchmark run's files from its runs.csv (docs/planners.md §5): figures.csv, variants.csv,
// settings.csv, report.md and the plots, and the run's status. A run assembles them when its
// cells end, a merge of shards (shard.cpp) from the shards' rows, so both give the same files.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/planbench/bench.hpp"

namespace flipper::planbench::detail {

/// What report.md says beside the tables.
struct ReportHead {
  std::string name, file;  ///< the experiment's
  std::size_t worlds = 0, planners = 0, cells = 0;
  int repetitions = 1;
  std::string measured_on;  ///< "HOST (N cores, load L at the start)", one per shard merged
  std::string shard_note;   ///< a shard's own paragraph ("" for a whole run)
};

/// The report's host text for one process: "NAME (N cores, load L at the start)".
std::string measured_on(const nlohmann::json& host, const std::string& load);
/// The 1-minute load average with two decimals, or "unknown".
std::string load_text();

/// complete: every task answered; partial: some tasks' processes died; failed: all did.
std::string run_status(std::size_t failures, std::size_t rows);

/// Reads RUN/runs.csv and writes the files made from it; draws the plots when `plots`. The
/// result's cells are head.cells; its status, run_status.
BenchResult assemble_bench(const std::string& run_dir, const ReportHead& head,
                           const nlohmann::json& failures, bool plots);

}  // namespace flipper::planbench::detail
