#pragma once
/// @file experiment.hpp
/// Experiment files (configs/experiments/*.yaml; docs/experiments.md §4):
/// @code
///   name: Ablation on the dev split
///   config: ../default.yaml           # optional (default: the embedded config)
///   corpus: ../../data/study2018/dev  # relative paths: against this file's directory
///   runs: [sep2018/FridayMorning]     # optional (default: every run)
///   max_queries: 0                    # optional, per run
///   bodies: accepted                  # optional: a definition's body lines mean the programs
///                                     # the user accepted for them (the logged formulas), as
///                                     # the 2018 server induced; `reparsed`: parse the text
///   set: [induction.generalize=false] # optional, applied to every variant
///   variants:                         # optional (default: one variant "plain")
///     - {name: plain, set: []}
///     - {name: alignment, set: [induction.alignment=true]}
///   sweep:                            # optional: a grid, crossed with the variants
///     planner.plugin: [astar, ompl]
///     planner.params.seed: [1, 2, 3]
///   isolation: process                # optional (default): each variant in its own process,
///                                     # also with --jobs 1; `none`: in this process
///   kill_after_s: 86400               # optional: wall-clock backstop of one variant's process
/// @endcode
/// With isolation, a variant whose process dies (a plugin's crash, a hang the backstop ends)
/// costs that variant only: the run finishes with the others, its manifest `status: partial`
/// (or `failed` when none finished) and a `failed` list naming each lost variant and its cause
/// (docs/experiments.md §4).
/// Each variant replays the same runs with its overrides after the run's mode keys, so a
/// variant may switch alignment back on. A sweep's grid points are crossed with the hand-written
/// variants (each variant at each point; without `variants`, the points alone); a point's
/// settings come after the variant's. Results: one run folder (flipper/record/run_folder.hpp)
/// with manifest.json, figures.csv, variants.csv, settings.csv, report.md, plots, and a folder
/// per variant (metrics.json, CSV files, that variant's figures.csv and plots).

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "flipper/record/figures.hpp"
#include "flipper/record/plots.hpp"
#include "flipper/record/sweep.hpp"

namespace flipper::replay {

struct ExperimentVariant {
  std::string name;
  std::vector<std::string> sets;
};

struct Experiment {
  std::string name = "Replay";
  std::string file;  ///< the experiment file ("" for a replay given by options alone)
  std::optional<std::string> config;
  std::string corpus;
  std::vector<std::string> runs;
  int max_queries = 0;
  bool reparse_bodies = false;  ///< `bodies: reparsed` (docs/experiments.md §4)
  std::vector<std::string> sets;
  std::vector<ExperimentVariant> variants;
  std::vector<record::SweepAxis> sweep;
  bool isolate = true;       ///< `isolation: process`: every variant in a child process
  int kill_after_s = 86400;  ///< the far wall-clock backstop of one variant's process
};

/// Resolves `path`, written in `file`, against the directory `file` is in (the path rule,
/// docs/usage.md); absolute and empty paths stay.
std::string resolve_in_file(const std::string& file, const std::string& path);
/// Reads an experiment file. Throws sdk::Error(bad_config) naming the file and key.
Experiment load_experiment(const std::string& path);

/// The experiment as a manifest records it (every path absolute), and back: a check or a merge
/// reads the experiment from the manifest, not from the file, which may have changed since.
nlohmann::json experiment_json(const Experiment& e);
Experiment experiment_from_json(const nlohmann::json& j);

/// One variant to run: what it is (name, folder, condition, seed, settings), its `--set`
/// assignments in order (experiment, variant, sweep point) and notes (a sweep setting left out
/// because the variant's plugin does not declare it).
struct PlannedVariant {
  record::VariantInfo info;
  std::vector<std::string> sets;
  std::vector<std::string> notes;
};
/// The variants of an experiment in order: hand-written variants × sweep points. A sweep key
/// `SECTION.params.NAME` is left out, with a note, for a variant whose SECTION plugin does not
/// declare NAME (astar has no seed: `planner.params.seed` applies to ompl only), and is an error
/// when no variant's plugin declares it. Throws sdk::Error(bad_config) for two variants with one
/// folder name.
std::vector<PlannedVariant> plan_variants(const Experiment& e);

struct RunOptions {
  std::string out;  ///< the parent folder of the run folder
  int jobs = 1;     ///< variants in parallel processes (at most this many)
  std::optional<record::Shard> shard;
  bool plots = true;
  /// Progress of one variant: commands done, commands total, the current run. Called in the
  /// process that replays the variant.
  std::function<void(const std::string& variant, std::size_t, std::size_t, const std::string&)>
      progress;
};

struct RunSummary {
  std::string run_dir;
  std::vector<record::VariantInfo> variants;  ///< those run here (a shard's part)
  std::vector<record::Figure> figures;
  record::PlotOutcome plots;
  std::string status;               ///< the manifest's: complete, partial or failed
  std::vector<std::string> failed;  ///< "VARIANT: CAUSE" of each variant that did not finish
};

/// Runs the experiment (the shard's variants, when sharded) into a new run folder under
/// options.out and writes its manifest, figures, report and plots. Isolated (the default), a
/// variant that fails or whose process dies is listed in the manifest's `failed` and the others
/// finish (RunSummary::failed). In-process (`isolation: none`), a variant that fails leaves the
/// manifest with status "failed" and throws its error.
RunSummary run_experiment(const Experiment& e, const RunOptions& options);

/// Writes a run's figures.csv, variants.csv, settings.csv, report.md and plots from its
/// manifest and its variants' folders, and completes the manifest (status, finish time,
/// plots). Used after running and after merging.
RunSummary assemble_run(const std::string& run_dir, nlohmann::json manifest, bool plots);

}  // namespace flipper::replay
