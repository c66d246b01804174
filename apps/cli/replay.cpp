// flipper replay --config F --corpus DIR --out DIR [--experiment FILE] [--runs a,b]
//                [--max-queries N] [--set k=v]...
// Replays a corpus split through kernel sessions and writes metrics, SVG figures and report.md.
// Command-line options override the experiment file; --set applies to every variant.
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/replay/experiment.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {
namespace {

struct ReplayArgs {
  std::string corpus, out, experiment, runs;
  int max_queries = -1;
  bool json = false;
};

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// A bar on a terminal (redrawn in place), plain lines every 5 % otherwise.
class Progress {
 public:
  Progress() : tty_(isatty(STDERR_FILENO) != 0) {}
  void operator()(const std::string& variant, std::size_t done, std::size_t total,
                  const std::string& run) {
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
  bool tty_;
  int last_ = -1;
  std::string variant_;
};

int run_replay(const CommonOptions& common, const ReplayArgs& args) {
  using namespace kernel::replay;
  Experiment e;
  if (!args.experiment.empty()) e = load_experiment(args.experiment);
  if (!common.config_file.empty()) e.config = common.config_file;
  if (!args.corpus.empty()) e.corpus = args.corpus;
  if (!args.runs.empty()) e.runs = split_commas(args.runs);
  if (args.max_queries >= 0) e.max_queries = args.max_queries;
  e.sets.insert(e.sets.end(), common.overrides.begin(), common.overrides.end());
  if (e.corpus.empty()) {
    return report_error("replay", "bad_config",
                        "no corpus (give --corpus DIR or an experiment with 'corpus')", kExitUsage);
  }
  Progress progress;
  auto variants = run_experiment(e, args.out, std::ref(progress));
  if (args.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& v : variants)
      list.push_back({{"variant", v.name},
                      {"status_agree", v.metrics.overall.agree},
                      {"queries", v.metrics.overall.n},
                      {"accepts_matched", v.metrics.exec.matched},
                      {"accepts", v.metrics.exec.accepts},
                      {"metrics", args.out + "/" + v.name + "/metrics.json"}});
    std::cout << nlohmann::json{{"variants", std::move(list)},
                                {"report", args.out + "/report.md"}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  for (const auto& v : variants)
    std::cout << v.name << ": status agreement " << v.metrics.overall.agree << "/"
              << v.metrics.overall.n << ", accepts matched " << v.metrics.exec.matched << "/"
              << v.metrics.exec.accepts << "\n";
  std::cout << "report: " << args.out << "/report.md\n";
  return kExitOk;
}

}  // namespace

void add_replay_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "replay", "Replay a user-study corpus split; write metrics, SVG figures and report.md");
  static CommonOptions opts;
  static ReplayArgs args;
  add_common_options(*cmd, opts);
  cmd->add_option("--corpus", args.corpus, "Corpus split directory (overrides the experiment)");
  cmd->add_option("--out", args.out, "Output directory")->required();
  cmd->add_option("--experiment", args.experiment, "Experiment file (configs/experiments/*.yaml)");
  cmd->add_option("--runs", args.runs, "Runs to replay, comma-separated (default: all)");
  cmd->add_option("--max-queries", args.max_queries, "Per run: stop before the (N+1)-th query");
  cmd->add_flag("--json", args.json, "Print the per-variant summary as one JSON object");
  on_run(*cmd, [] {
    try {
      return run_replay(opts, args);
    } catch (const sdk::Error& e) {
      return report_error("replay", e.code(), e.what(), status_for(e.code()));
    }
  });
}
}  // namespace flipper::cli
