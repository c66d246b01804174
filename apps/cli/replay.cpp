// flipper replay --out PARENT [--experiment FILE] [--config F] [--corpus DIR] [--runs a,b]
//                [--max-queries N] [--set k=v]... [--jobs N] [--shard I/N] [--print TABLE]
//                [--json] [--no-plots]
// flipper replay check RUN [--jobs N] [--out PARENT]
// flipper replay merge RUN... --out PARENT [--no-plots]
// flipper replay compare RUN_A RUN_B [--all]
// flipper replay plot RUN
// flipper replay verify REC [--config F] [--set k=v]...
// flipper replay repair --corpus DIR [--runs a,b] [--config F] [--set k=v]...
// Replays a corpus split through kernel sessions into a new run folder under --out: manifest,
// figures (tidy CSV), metrics, report.md and plots (docs/experiments.md). Command-line options
// override the experiment file; --set applies to every variant.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/record/compare.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/replay/check.hpp"
#include "flipper/replay/corpus.hpp"
#include "flipper/replay/experiment.hpp"
#include "flipper/replay/output.hpp"
#include "flipper/replay/repair_hits.hpp"
#include "flipper/replay/replayer.hpp"
#include "flipper/replay/verify.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {
namespace {

using replay::RunSummary;

struct ReplayArgs {
  std::string corpus, out, experiment, runs, shard, print;
  int max_queries = -1;
  int jobs = -1;  ///< -1 (not given): the cores available
  bool json = false, no_plots = false, progress = false;
};

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// A bar on a terminal (redrawn in place) for one variant at a time; plain lines every 5 % when
// variants run in parallel (their lines interleave). Quiet when standard error is not a
// terminal (logs, CI).
class Progress {
 public:
  /// Lines go to standard error when it is a terminal, or always with `force` (--progress).
  Progress(bool plain, bool force)
      : terminal_(force || isatty(STDERR_FILENO) != 0),
        tty_(!plain && isatty(STDERR_FILENO) != 0) {}
  void operator()(const std::string& variant, std::size_t done, std::size_t total,
                  const std::string& run) {
    if (!terminal_) return;
    const int percent = total ? static_cast<int>(100 * done / total) : 100;
    if (tty_) {
      const int width = 30, filled = percent * width / 100;
      std::fprintf(stderr, "\r%-10s [%-*s] %3d%% %zu/%zu %-28s", variant.c_str(), width,
                   std::string(static_cast<std::size_t>(filled), '#').c_str(), percent, done, total,
                   run.c_str());
      if (done == total) std::fputc('\n', stderr);
    } else if (percent / 5 != last_ / 5 || done == total || variant != variant_) {
      std::fprintf(stderr, "replay %s: %d%% (%zu/%zu) %s\n", variant.c_str(), percent, done, total,
                   run.c_str());
    }
    last_ = percent;
    variant_ = variant;
  }

 private:
  bool terminal_, tty_;
  int last_ = -1;
  std::string variant_;
};

int jobs_or_cores(int jobs) {
  return jobs > 0 ? jobs : record::available_cores();
}

// Where plots went, or why not (a note on stderr, never a failure of the run).
void say_plots(const record::PlotOutcome& plots) {
  if (plots.status == record::PlotOutcome::Status::drawn)
    std::cerr << plots.message;
  else
    std::cerr << "flipper replay: note: " << plots.message << "\n";
}

std::string one_table(const std::string& name, const RunSummary& s) {
  const record::FigureTable t(s.figures);
  if (name == "headline") return replay::headline_text(t, s.variants);
  if (name == "oracles") return replay::oracles_text(t, s.variants);
  if (name == "rules") return replay::rules_text(t, s.variants);
  if (name == "variants") return replay::variants_table(t, s.variants);
  if (name == "planner") return replay::planner_table(t, s.variants);
  if (name == "seeds") return replay::seeds_table(s.figures, s.variants);
  throw sdk::Error(
      sdk::codes::kBadRequest,
      "--print '" + name + "': no such table (headline, variants, oracles, rules, planner, seeds)");
}

// The --print tables: what README blocks generate (scripts/readme-figures). `names` is one
// table or several, comma-separated, printed in that order.
std::string table_text(const std::string& names, const RunSummary& s) {
  std::string out;
  for (const auto& name : split_commas(names)) out += one_table(name, s);
  return out;
}

int run_replay(const CommonOptions& common, const ReplayArgs& args) {
  using namespace replay;
  if (args.out.empty())
    return report_error("replay", "usage",
                        "--out PARENT is required: the run goes into a new folder under it "
                        "(see --help)",
                        kExitUsage);
  if (args.jobs != -1 && args.jobs < 1)
    return report_error("replay", "usage",
                        "--jobs must be at least 1 (got " + std::to_string(args.jobs) + ")",
                        kExitUsage);
  if (!args.print.empty()) table_text(args.print, {});  // an unknown table before the run
  Experiment e;
  if (!args.experiment.empty()) e = load_experiment(args.experiment);
  if (!common.config_file.empty())
    e.config = std::filesystem::absolute(common.config_file).lexically_normal().string();
  if (!args.corpus.empty())
    e.corpus = std::filesystem::absolute(args.corpus).lexically_normal().string();
  if (!args.runs.empty()) e.runs = split_commas(args.runs);
  if (args.max_queries >= 0) e.max_queries = args.max_queries;
  e.sets.insert(e.sets.end(), common.overrides.begin(), common.overrides.end());
  if (e.corpus.empty()) {
    return report_error("replay", "bad_config",
                        "no corpus (give --corpus DIR or an experiment with 'corpus')", kExitUsage);
  }
  RunOptions options;
  options.out = args.out;
  options.jobs = jobs_or_cores(args.jobs);
  if (!args.shard.empty()) options.shard = record::parse_shard(args.shard);
  options.plots = !args.no_plots;
  Progress progress(options.jobs > 1, args.progress);
  options.progress = std::ref(progress);
  const RunSummary s = run_experiment(e, options);
  // Variants whose process died: said on stderr, and the exit status says the run is not complete.
  const auto finish = [&s] {
    for (const auto& f : s.failed) std::cerr << "flipper replay: variant " << f << "\n";
    if (s.failed.empty()) return kExitOk;
    std::cerr << "flipper replay: run " << s.status << ": " << s.failed.size()
              << " variant(s) did not finish (manifest `failed`, report.md)\n";
    return kExitFailed;
  };

  const record::FigureTable t(s.figures);
  auto figure = [&](const std::string& v, const std::string& metric) {
    return record::show_value(t.find(v, "ours", "all", metric).value_or(0));
  };
  if (args.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& v : s.variants)
      list.push_back(
          {{"variant", v.name},
           {"status_agree", t.find(v.name, "ours", "all", "agree").value_or(0)},
           {"queries", t.find(v.name, "ours", "all", "queries").value_or(0)},
           {"accepts_matched", t.find(v.name, "ours", "all", "accepts_matched").value_or(0)},
           {"accepts", t.find(v.name, "ours", "all", "accepts").value_or(0)},
           {"metrics", s.run_dir + "/" + v.directory + "/metrics.json"}});
    std::cout << nlohmann::json{{"run", s.run_dir},
                                {"variants", std::move(list)},
                                {"figures", s.run_dir + "/figures.csv"},
                                {"report", s.run_dir + "/report.md"}}
                     .dump(2)
              << "\n";
    return finish();
  }
  // With --print the table is the only standard output (a README block's content).
  std::ostream& summary = args.print.empty() ? std::cout : std::cerr;
  for (const auto& v : s.variants)
    summary << v.name << ": status agreement " << figure(v.name, "agree") << "/"
            << figure(v.name, "queries") << ", accepts matched "
            << figure(v.name, "accepts_matched") << "/" << figure(v.name, "accepts") << "\n";
  summary << "run: " << s.run_dir << "\nreport: " << s.run_dir << "/report.md\n";
  say_plots(s.plots);
  if (!args.print.empty()) std::cout << table_text(args.print, s);
  return finish();
}

struct CheckArgs {
  std::string run, out;
  int jobs = -1;  ///< -1 (not given): the cores available
};

struct MergeArgs {
  std::vector<std::string> runs;
  std::string out;
  bool no_plots = false;
};

struct CompareArgs {
  std::string a, b;
  bool all = false;
};

void add_check(CLI::App& replay) {
  auto* cmd = replay.add_subcommand(
      "check", "Re-run a recorded run from its manifest and report every figure that differs");
  static CheckArgs args;
  cmd->add_option("run", args.run, "The run folder")->required();
  cmd->add_option("--jobs", args.jobs, "Variants in parallel processes (default: the cores)");
  cmd->add_option("--out", args.out, "Keep the re-run under this folder (default: removed)");
  on_run(*cmd, [] {
    return reporting_errors("replay check", [] {
      if (args.jobs != -1 && args.jobs < 1)
        throw sdk::Error(sdk::codes::kBadRequest,
                         "--jobs must be at least 1 (got " + std::to_string(args.jobs) + ")");
      const auto r = replay::check_run(args.run, jobs_or_cores(args.jobs), args.out);
      std::cout << r.text;
      return r.differs() ? kExitFailed : kExitOk;
    });
  });
}

void add_merge(CLI::App& replay) {
  auto* cmd =
      replay.add_subcommand("merge", "Merge the shard runs of one experiment into one new run");
  static MergeArgs args;
  cmd->add_option("runs", args.runs, "The shard run folders")->required();
  cmd->add_option("--out", args.out, "Parent folder of the merged run")->required();
  cmd->add_flag("--no-plots", args.no_plots, "Do not draw the plots");
  on_run(*cmd, [] {
    return reporting_errors("replay merge", [] {
      std::vector<std::string> warnings;
      const auto s = replay::merge_runs(args.runs, args.out, !args.no_plots, warnings);
      for (const auto& w : warnings) std::cerr << "flipper replay merge: warning: " << w << "\n";
      std::cout << "merged " << args.runs.size() << " shards, " << s.variants.size()
                << " variants\nrun: " << s.run_dir << "\nreport: " << s.run_dir << "/report.md\n";
      say_plots(s.plots);
      return kExitOk;
    });
  });
}

void add_compare(CLI::App& replay) {
  auto* cmd = replay.add_subcommand(
      "compare", "Two runs side by side: figures per variant (over seeds where there are)");
  static CompareArgs args;
  cmd->add_option("run_a", args.a, "Run A")->required();
  cmd->add_option("run_b", args.b, "Run B")->required();
  cmd->add_flag("--all", args.all, "List every figure, not only those that differ");
  on_run(*cmd, [] {
    return reporting_errors("replay compare", [] {
      record::ComparisonCounts counts;
      std::cout << record::compare_runs(record::read_run_figures(args.a),
                                        record::read_run_figures(args.b), args.all, &counts);
      if (counts.compared == 0) {
        std::cerr << "flipper replay compare: nothing compared (the runs share no condition)\n";
        return kExitFailed;
      }
      return kExitOk;
    });
  });
}

void add_plot(CLI::App& replay) {
  auto* cmd = replay.add_subcommand("plot", "Draw (again) a run's plots from its CSV files");
  static std::string run;
  cmd->add_option("run", run, "The run folder")->required();
  on_run(*cmd, [] {
    return reporting_errors("replay plot", [] {
      if (!record::is_run_folder(run))
        throw sdk::Error(sdk::codes::kBadRequest, "'" + run + "' is not a run folder");
      const auto plots = record::draw_plots("replay_plots.py", run);
      say_plots(plots);
      return plots.status == record::PlotOutcome::Status::failed ? kExitFailed : kExitOk;
    });
  });
}

// A studio recording's every answer again, byte for byte (docs/experiments.md §8).
void add_verify(CLI::App& replay) {
  auto* cmd = replay.add_subcommand(
      "verify",
      "Replay a studio study recording's exchanges and compare every answer byte for byte");
  static CommonOptions opts;
  static std::string dir;
  cmd->add_option("recording", dir, "The recording folder (study.json, exchanges.jsonl)")
      ->required();
  add_common_options(*cmd, opts);
  on_run(*cmd, [] {
    return reporting_errors("replay verify", [] {
      replay::VerifyResult r;
      try {
        r = replay::verify_recording(dir, {config_file(opts), opts.overrides});
      } catch (const sdk::Error& e) {
        if (e.code() != std::string(replay::kBadCorpus)) throw;
        return report_error("replay verify", e.code(), e.what(), kExitUsage);
      }
      for (const auto& note : r.notes) std::cerr << "flipper replay verify: note: " << note << "\n";
      if (!r.equal) {
        std::cout << "flipper replay verify: " << r.divergence;
        return kExitFailed;
      }
      std::cout << r.exchanges << " exchanges, every answer equal byte for byte (ms excluded)\n";
      return kExitOk;
    });
  });
}

// The repair suggestions' hit rate on a corpus split (repair_hits.hpp, docs/replay.md).
void add_repair(CLI::App& replay) {
  auto* cmd = replay.add_subcommand(
      "repair",
      "Replay a corpus split asking repairs for the queries the original could not parse, and "
      "count how often the top 3 suggestions hold the sentence the user accepted next");
  static CommonOptions opts;
  static std::string corpus, runs;
  cmd->add_option("--corpus", corpus, "Corpus split directory")->required();
  cmd->add_option("--runs", runs, "Runs to replay, comma-separated (default: all)");
  add_common_options(*cmd, opts);
  on_run(*cmd, [] {
    return reporting_errors("replay repair", [] {
      const replay::Corpus c = replay::load_corpus(corpus);
      replay::ReplayOptions o;
      o.config_file = config_file(opts);
      o.sets = opts.overrides;
      o.runs = split_commas(runs);
      o.repair = true;
      const replay::ReplayResult r = replay::replay(c, o);
      std::cout << replay::repair_hits_text(replay::repair_hits(c, r));
      return kExitOk;
    });
  });
}

}  // namespace

void add_replay_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "replay",
      "Replay a user-study corpus split into a new run folder (manifest, figures, report, plots)");
  static CommonOptions opts;
  static ReplayArgs args;
  add_common_options(*cmd, opts);
  cmd->add_option("--corpus", args.corpus, "Corpus split directory (overrides the experiment)");
  cmd->add_option("--out", args.out,
                  "Parent folder: the run goes into a new folder under it (never overwritten)");
  cmd->add_option("--experiment", args.experiment, "Experiment file (configs/experiments/*.yaml)");
  cmd->add_option("--runs", args.runs, "Runs to replay, comma-separated (default: all)");
  cmd->add_option("--max-queries", args.max_queries, "Per run: stop before the (N+1)-th query");
  cmd->add_option("--jobs", args.jobs,
                  "Variants in parallel processes, at most N (default: the cores)");
  cmd->add_option("--shard", args.shard,
                  "Run only shard I of N of the variants (I from 0), for merge");
  cmd->add_option("--print", args.print,
                  "Print only these tables (comma-separated) to standard output: headline, "
                  "variants, oracles, rules, planner, seeds");
  cmd->add_flag("--json", args.json, "Print the per-variant summary as one JSON object");
  cmd->add_flag("--no-plots", args.no_plots, "Do not draw the plots");
  cmd->add_flag("--progress", args.progress,
                "Progress lines on standard error even when it is not a terminal");
  cmd->require_subcommand(0, 1);
  add_check(*cmd);
  add_merge(*cmd);
  add_compare(*cmd);
  add_plot(*cmd);
  add_verify(*cmd);
  add_repair(*cmd);
  on_run(*cmd, [cmd] {
    if (!cmd->get_subcommands().empty())
      return kExitOk;  // check, merge, compare, plot, verify, repair
    return reporting_errors("replay", [] { return run_replay(opts, args); });
  });
}
}  // namespace flipper::cli
