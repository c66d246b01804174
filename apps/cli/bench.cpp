// flipper bench planners --experiment FILE --out PARENT [--config F] [--set k=v]... [--jobs N]
//                        [--shard I/N] [--print results|intervals|timing] [--no-plots]
// flipper bench planners merge RUN... --out PARENT [--no-plots]
// flipper bench planners plot RUN
// The planner benchmark (docs/planners.md §5): tasks × worlds × planners × seeds, any planner
// plugin by name (in-tree, or out-of-tree through plugin_paths), one row per plan in runs.csv of
// a new run folder under --out, with manifest, summary tables (report.md) and plots.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/planbench/bench.hpp"
#include "flipper/planbench/experiment.hpp"
#include "flipper/planbench/shard.hpp"
#include "flipper/planbench/summary.hpp"
#include "flipper/record/compare.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {
namespace {

struct PlannerBenchArgs {
  std::string experiment, out, print, shard;
  int jobs = -1;  ///< -1 (not given): the cores available
  bool no_plots = false;
};

int guarded(const char* name, const std::function<int()>& f) {
  try {
    return f();
  } catch (const sdk::Error& e) {
    return report_error(name, e.code(), e.what(), status_for(e.code()));
  }
}

// The --print tables (what a README block generates): results, intervals, timing,
// comma-separated.
std::string print_tables(const std::string& names, const std::string& run_dir) {
  std::string out;
  std::size_t from = 0;
  while (from <= names.size()) {
    const std::size_t comma = std::min(names.find(',', from), names.size());
    const std::string name = names.substr(from, comma - from);
    from = comma + 1;
    if (name.empty()) continue;
    if (name != "results" && name != "intervals" && name != "timing")
      throw sdk::Error(sdk::codes::kBadRequest,
                       "--print '" + name + "': no such table (results, intervals, timing)");
    if (run_dir.empty()) continue;  // checking the names only
    const auto runs = record::read_csv(run_dir + "/runs.csv");
    if (!out.empty()) out += "\n";  // Markdown: a blank line ends a table
    out += name == "results"     ? planbench::results_table(runs)
           : name == "intervals" ? planbench::intervals_table(runs)
                                 : planbench::timing_table(runs);
  }
  return out;
}

// One progress line on a terminal, redrawn in place: cells done / total, rate, time left. Quiet
// when standard error is not a terminal (logs, CI).
class CellProgress {
 public:
  CellProgress() : tty_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()) {}
  void operator()(std::size_t done, std::size_t total) const {
    if (!tty_) return;
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double rate = s > 0 ? static_cast<double>(done) / s : 0;
    const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0;
    std::fprintf(stderr, "\rbench planners: %zu/%zu cells, %.1f cells/s, ETA %.0f s   ", done,
                 total, rate, left);
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
  }

 private:
  bool tty_;
  std::chrono::steady_clock::time_point start_;
};

// What a finished run says: where it is, its plots, its lost tasks (exit 1 when any).
int finish_run(const planbench::BenchResult& result, bool plots, const std::string& print) {
  std::ostream& summary = print.empty() ? std::cout : std::cerr;
  summary << "planner benchmark: " << result.cells << " cells, " << result.runs
          << " plans\nrun: " << result.run_dir << "\nreport: " << result.run_dir << "/report.md\n";
  if (result.plots.status == record::PlotOutcome::Status::drawn)
    std::cerr << result.plots.message;
  else if (plots)
    std::cerr << "flipper bench planners: note: " << result.plots.message << "\n";
  if (!print.empty()) std::cout << print_tables(print, result.run_dir);
  if (result.failures > 0) {
    std::cerr << "flipper bench planners: " << result.failures
              << " task(s) lost their process (run " << result.status
              << "; see the manifest's `failed` list and report.md)\n";
    return kExitFailed;
  }
  return kExitOk;
}

int check_jobs(int jobs) {
  if (jobs != -1 && jobs < 1)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "--jobs must be at least 1 (got " + std::to_string(jobs) + ")");
  return jobs > 0 ? jobs : record::available_cores();
}

int run_planner_bench(const CommonOptions& common, const PlannerBenchArgs& args) {
  if (args.experiment.empty())
    return report_error("bench planners", "usage",
                        "--experiment FILE is required (e.g. configs/experiments/planners.yaml)",
                        kExitUsage);
  if (args.out.empty())
    return report_error("bench planners", "usage",
                        "--out PARENT is required: the run goes into a new folder under it",
                        kExitUsage);
  if (args.jobs != -1 && args.jobs < 1)
    return report_error("bench planners", "usage",
                        "--jobs must be at least 1 (got " + std::to_string(args.jobs) + ")",
                        kExitUsage);
  print_tables(args.print, "");
  const std::optional<record::Shard> shard =
      args.shard.empty() ? std::nullopt : std::optional(record::parse_shard(args.shard));
  const auto experiment = planbench::load_bench_experiment(args.experiment);
  planbench::BenchOptions options;
  options.config = common.config_file;
  options.overrides = common.overrides;
  options.out = args.out;
  options.jobs = args.jobs > 0 ? args.jobs : record::available_cores();
  options.plots = !args.no_plots;
  options.progress = CellProgress();
  options.shard = shard;
  return finish_run(planbench::run_bench(experiment, options), options.plots, args.print);
}

// flipper bench planners merge RUN... --out PARENT: the N shard runs of one benchmark joined
// into one run, the files of a run made in one piece (docs/planners.md §5, "Shards").
void add_merge(CLI::App& planners) {
  auto* cmd = planners.add_subcommand(
      "merge", "Merge the shard runs (--shard I/N) of one benchmark into one new run");
  static std::vector<std::string> runs;
  static std::string out;
  static bool no_plots = false;
  cmd->add_option("runs", runs, "The shard run folders, every I of 0..N-1 once")->required();
  cmd->add_option("--out", out, "Parent folder of the merged run")->required();
  cmd->add_flag("--no-plots", no_plots, "Do not draw the plots");
  on_run(*cmd, [] {
    return guarded("bench planners merge", [] {
      std::vector<std::string> warnings;
      const auto result = planbench::merge_bench(runs, out, !no_plots, warnings);
      for (const auto& w : warnings)
        std::cerr << "flipper bench planners merge: warning: " << w << "\n";
      std::cout << "merged " << runs.size() << " shards\n";
      return finish_run(result, !no_plots, "");
    });
  });
}

void add_planners(CLI::App& bench) {
  auto* cmd = bench.add_subcommand(
      "planners",
      "Benchmark planner plugins: tasks x worlds x planners x seeds into a new run folder");
  static CommonOptions opts;
  static PlannerBenchArgs args;
  add_common_options(*cmd, opts);
  cmd->add_option("--experiment", args.experiment,
                  "Benchmark experiment file (configs/experiments/planners.yaml)");
  cmd->add_option("--out", args.out,
                  "Parent folder: the run goes into a new folder under it (never overwritten)");
  cmd->add_option("--jobs", args.jobs,
                  "Cells (world x planner x seed) in parallel processes (default: the cores)");
  cmd->add_option("--print", args.print,
                  "Print only these tables to standard output: results, intervals (deterministic), "
                  "timing");
  cmd->add_option("--shard", args.shard,
                  "Run only shard I of N (I from 0): the plans whose row index r in the whole "
                  "run has r mod N = I; join the shards with `merge`");
  cmd->add_flag("--no-plots", args.no_plots, "Do not draw the plots");
  cmd->require_subcommand(0, 1);
  add_merge(*cmd);
  auto* plot = cmd->add_subcommand("plot", "Draw (again) a benchmark run's plots from runs.csv");
  static std::string run;
  plot->add_option("run", run, "The run folder")->required();
  on_run(*plot, [] {
    return guarded("bench planners plot", [] {
      if (!record::is_run_folder(run))
        throw sdk::Error(sdk::codes::kBadRequest, "'" + run + "' is not a run folder");
      const auto plots = record::draw_plots("planner_bench_plots.py", run);
      std::cerr << plots.message
                << (plots.message.empty() || plots.message.back() == '\n' ? "" : "\n");
      return plots.status == record::PlotOutcome::Status::drawn ? kExitOk : kExitFailed;
    });
  });
  auto* resume = cmd->add_subcommand(
      "resume",
      "Finish an interrupted benchmark run in its own folder (rows kept, checksummed inputs)");
  static std::string resume_run;
  static int resume_jobs = -1;
  static bool resume_no_plots = false;
  resume->add_option("run", resume_run, "The interrupted run folder (manifest status running)")
      ->required();
  resume->add_option("--jobs", resume_jobs, "Cells in parallel processes (default: the cores)");
  resume->add_flag("--no-plots", resume_no_plots, "Do not draw the plots");
  on_run(*resume, [] {
    return guarded("bench planners resume", [] {
      return finish_run(
          planbench::resume_bench(resume_run, check_jobs(resume_jobs), !resume_no_plots),
          !resume_no_plots, "");
    });
  });
  auto* check = cmd->add_subcommand(
      "check", "Re-run a benchmark run from its manifest and report every figure that differs");
  static std::string check_run, check_out;
  static int check_jobs_n = -1;
  check->add_option("run", check_run, "The run folder")->required();
  check->add_option("--jobs", check_jobs_n, "Cells in parallel processes (default: the cores)");
  check->add_option("--out", check_out, "Keep the re-run under this folder (default: removed)");
  on_run(*check, [] {
    return guarded("bench planners check", [] {
      const auto r = planbench::check_bench(check_run, check_jobs(check_jobs_n), check_out);
      std::cout << r.text;
      if (!r.rerun.empty()) std::cout << "re-run: " << r.rerun << "\n";
      return r.differing > 0 || r.compared == 0 ? kExitFailed : kExitOk;
    });
  });
  auto* compare = cmd->add_subcommand(
      "compare",
      "Two benchmark runs side by side: each cell's figures (over seeds where there are)");
  static std::string compare_a, compare_b;
  static bool compare_all = false;
  compare->add_option("run_a", compare_a, "Run A")->required();
  compare->add_option("run_b", compare_b, "Run B")->required();
  compare->add_flag("--all", compare_all, "List every figure, not only those that differ");
  on_run(*compare, [] {
    return guarded("bench planners compare", [] {
      for (const auto* folder : {&compare_a, &compare_b})
        if (!record::is_run_folder(*folder))
          throw sdk::Error(sdk::codes::kBadRequest, "'" + *folder + "' is not a run folder");
      record::ComparisonCounts counts;
      std::cout << record::compare_runs(record::read_run_figures(compare_a),
                                        record::read_run_figures(compare_b), compare_all, &counts);
      if (counts.compared == 0) {
        std::cerr << "flipper bench planners compare: nothing compared (the runs share no cell)\n";
        return kExitFailed;
      }
      return kExitOk;
    });
  });
  on_run(*cmd, [cmd] {
    if (!cmd->get_subcommands().empty()) return kExitOk;  // plot, resume, check, compare, merge
    return guarded("bench planners", [] { return run_planner_bench(opts, args); });
  });
}

}  // namespace

void add_bench_command(CLI::App& app) {
  // --config and --set belong to the benchmark (`bench planners --set ...`), as on replay's.
  auto* cmd = app.add_subcommand("bench", "Benchmarks with run records (planners)");
  cmd->require_subcommand(1);
  add_planners(*cmd);
}

}  // namespace flipper::cli
