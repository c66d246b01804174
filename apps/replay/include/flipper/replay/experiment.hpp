#pragma once
/// @file experiment.hpp
/// Experiment files (configs/experiments/*.yaml):
/// @code
///   name: Ablation on the dev split
///   config: ../default.yaml           # optional (default: the embedded config)
///   corpus: ../../data/study2018/dev  # relative paths: against this file's directory
///   runs: [sep2018/FridayMorning]     # optional (default: every run)
///   max_queries: 0                    # optional, per run
///   set: [induction.generalize=false] # optional, applied to every variant
///   variants:                         # optional (default: one variant "plain")
///     - {name: plain, set: []}
///     - {name: alignment, set: [induction.alignment=true]}
/// @endcode
/// Each variant replays the same runs with its overrides after the run's mode keys, so a
/// variant may switch alignment back on. Results: <out>/<variant>/ (metrics, CSV, SVG) and
/// <out>/report.md with the variants side by side.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipper/replay/output.hpp"

namespace flipper::kernel::replay {

struct ExperimentVariant {
  std::string name;
  std::vector<std::string> sets;
};

struct Experiment {
  std::string name = "Replay";
  std::optional<std::string> config;
  std::string corpus;
  std::vector<std::string> runs;
  int max_queries = 0;
  std::vector<std::string> sets;
  std::vector<ExperimentVariant> variants;
};

/// Resolves `path`, written in `file`, against the directory `file` is in (the path rule,
/// README "Using it"); absolute and empty paths stay.
std::string resolve_in_file(const std::string& file, const std::string& path);
/// Reads an experiment file. Throws sdk::Error(bad_config) naming the file and key.
Experiment load_experiment(const std::string& path);

/// Runs every variant and writes the results and report into `out`. Returns the variants.
std::vector<Variant> run_experiment(
    const Experiment& experiment, const std::string& out,
    const std::function<void(const std::string& variant, std::size_t, std::size_t,
                             const std::string& run)>& progress = {});

}  // namespace flipper::kernel::replay
