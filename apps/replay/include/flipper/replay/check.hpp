#pragma once
/// @file check.hpp
/// Re-checking a run from its manifest, and merging the shards of one experiment into one run
/// (docs/experiments.md §§4, 6).

#include <string>
#include <vector>

#include "flipper/record/figures.hpp"
#include "flipper/replay/experiment.hpp"

namespace flipper::replay {

struct CheckResult {
  std::string rerun_dir;              ///< the re-run ("" when it was temporary and is removed)
  std::vector<std::string> warnings;  ///< provenance differences (record/manifest.hpp)
  record::FigureDiff diff;            ///< recorded (a) against re-run (b)
  /// Figures that differ, or figures in only one of the two: the run does not reproduce.
  bool differs() const {
    return !diff.changed.empty() || !diff.only_a.empty() || !diff.only_b.empty();
  }
  std::string text;  ///< the readable account (warnings, differences, timing apart)
};

/// Re-runs `run_dir`'s experiment (its shard, if it was one) from the manifest alone, with
/// `jobs` processes, into a new run under `keep_under` (or a temporary folder, removed
/// afterwards, when empty), and compares every figure. Throws sdk::Error(bad_request) when
/// `run_dir` is no complete replay run.
CheckResult check_run(const std::string& run_dir, int jobs, const std::string& keep_under);

/// Merges the shard runs of one experiment into a new run under `out`: refuses runs that are no
/// shards, shards of different experiments or corpora, different shard counts, a shard given
/// twice or missing, and variants missing or run twice. Differences of build or plugins between
/// the shards' machines are returned as warnings in `warnings`.
RunSummary merge_runs(const std::vector<std::string>& runs, const std::string& out, bool plots,
                      std::vector<std::string>& warnings);

}  // namespace flipper::replay
