// Running an experiment into a run folder, and assembling a run folder's shared files
// (experiment.hpp; docs/experiments.md).
#include <filesystem>
#include <iostream>
#include <set>

#include "flipper/kernel/config.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/replay/corpus.hpp"
#include "flipper/replay/experiment.hpp"
#include "flipper/replay/figures.hpp"
#include "flipper/replay/output.hpp"
#include "flipper/replay/replayer.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/config_schema.hpp"

namespace flipper::replay {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A variant's entry in the manifest: what it is, its config and plugins, its seeds.
json variant_json(const Experiment& e, const PlannedVariant& v) {
  const kernel::Config config = wiring::load_config(e.config, v.sets);
  json plugins = record::plugins_json(config);
  json seeds = json::object();
  for (const auto& p : plugins)
    for (auto it = p["params"].begin(); it != p["params"].end(); ++it) {
      const std::string key = p["section"].get<std::string>() + ".params." + it.key();
      if (record::is_seed_key(key)) seeds[key] = it.value();
    }
  json modes = json::object();
  for (const char* g : {"A", "B", "C"}) modes[g] = mode_overrides(g);
  return {{"name", v.info.name},
          {"directory", v.info.directory},
          {"condition", v.info.condition},
          {"seed", v.info.seed},
          {"sets", v.sets},
          {"notes", v.notes},
          {"mode_overrides", modes},
          {"config", record::config_json(config)},
          {"plugins", plugins},
          {"seeds", seeds}};
}

std::string stem_of(const Experiment& e) {
  return e.file.empty() ? std::string("replay") : fs::path(e.file).stem().string();
}

// Replays one variant and writes its folder: metrics.json, the CSV files, its figures.csv.
void run_variant(const Corpus& corpus, const Experiment& e, const PlannedVariant& v,
                 const std::string& run_dir, const RunOptions& options) {
  ReplayOptions o;
  o.config_file = e.config;
  o.sets = v.sets;
  o.runs = e.runs;
  o.max_queries = e.max_queries;
  o.reparse_bodies = e.reparse_bodies;
  if (options.progress)
    o.progress = [&](std::size_t done, std::size_t total, const std::string& run) {
      options.progress(v.info.name, done, total, run);
    };
  const ReplayResult result = replay(corpus, o);
  const Metrics m = compute_metrics(result);
  const std::string dir = run_dir + "/" + v.info.directory;
  write_metrics(dir, result, m);
  record::write_figures(dir + "/figures.csv", replay_figures(v.info.name, m));
}

}  // namespace

RunSummary run_experiment(const Experiment& e, const RunOptions& options) {
  if (e.corpus.empty())
    throw sdk::Error(sdk::codes::kBadConfig, "no corpus given (experiment 'corpus' or --corpus)");
  const Corpus corpus = load_corpus(e.corpus);
  std::vector<PlannedVariant> all = plan_variants(e);
  std::vector<PlannedVariant> planned;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (!options.shard || record::in_shard(i, *options.shard)) planned.push_back(all[i]);
  select_runs(corpus, e.runs);  // unknown runs are refused before anything is written

  json manifest = {{"format", 1},
                   {"kind", "replay"},
                   {"status", "running"},
                   {"build", record::build_json()},
                   {"source", record::source_json()},
                   {"host", record::host_json()},
                   {"command", record::command_json()},
                   {"started", record::utc_now()},
                   {"jobs", options.jobs},
                   {"experiment", experiment_json(e)},
                   {"grid_size", all.size()},
                   {"corpus", record::folder_json(e.corpus)}};
  manifest["shard"] = options.shard
                          ? json{{"index", options.shard->index}, {"count", options.shard->count}}
                          : json();
  json inputs = json::array();
  if (!e.file.empty()) inputs.push_back(record::file_json("experiment", e.file));
  manifest["inputs"] = inputs;
  json variants = json::array();
  std::set<std::string> notes;  // plugins that hide same-named ones, said at once
  for (const auto& v : planned) {
    variants.push_back(variant_json(e, v));
    for (const auto& note : record::shadow_notes(variants.back()["plugins"])) notes.insert(note);
  }
  for (const auto& note : notes) std::cerr << "flipper replay: note: " << note << "\n";
  manifest["variants"] = variants;

  std::string stem = stem_of(e);
  if (options.shard)
    stem += "-shard" + std::to_string(options.shard->index) + "of" +
            std::to_string(options.shard->count);
  const std::string run_dir = record::create_run_folder(options.out, stem);
  manifest["run"] = fs::path(run_dir).filename().string();
  record::write_manifest(run_dir, manifest);

  if (!e.isolate && (options.jobs <= 1 || planned.size() <= 1)) {
    try {
      for (const auto& v : planned) run_variant(corpus, e, v, run_dir, options);
    } catch (...) {
      manifest["status"] = "failed";
      manifest["finished"] = record::utc_now();
      record::write_manifest(run_dir, manifest);
      record::mark_latest(run_dir);
      throw;
    }
  } else {
    record::IsolationOptions isolation;
    isolation.jobs = options.jobs;
    isolation.wall_backstop_s = e.kill_after_s;
    const auto exits = record::run_isolated(
        planned.size(), isolation,
        [&](std::size_t i) {
          run_variant(corpus, e, planned[i], run_dir, options);
          return 0;
        },
        [&](const std::exception& ex) {
          const auto* err = dynamic_cast<const sdk::Error*>(&ex);
          std::cerr << "flipper replay: [" << (err ? err->code() : "internal") << "] " << ex.what()
                    << "\n";
        });
    json failed = json::array();
    for (std::size_t i = 0; i < exits.size(); ++i) {
      if (exits[i].ok()) continue;
      manifest["variants"][i]["status"] = exits[i].kind();
      manifest["variants"][i]["cause"] = exits[i].describe();
      failed.push_back({{"variant", planned[i].info.name},
                        {"status", exits[i].kind()},
                        {"cause", exits[i].describe()}});
    }
    manifest["failed"] = failed;
  }
  manifest["finished"] = record::utc_now();
  return assemble_run(run_dir, manifest, options.plots);
}

RunSummary assemble_run(const std::string& run_dir, json manifest, bool plots) {
  RunSummary summary;
  summary.run_dir = run_dir;
  std::size_t finished = 0;
  for (const auto& v : manifest.value("variants", json::array())) {
    if (v.contains("status") && v["status"] != "ok") {  // its process died: no figures
      summary.failed.push_back(v.at("name").get<std::string>() + ": " +
                               v.value("cause", std::string()));
      continue;
    }
    ++finished;
    record::VariantInfo info{v.at("name").get<std::string>(),
                             v.at("directory").get<std::string>(),
                             v.at("condition").get<std::string>(),
                             v.at("seed").get<std::string>(),
                             {}};
    // Settings: the experiment's and the variant's `--set` assignments, split at the first '='.
    for (const auto& s : v.at("sets")) {
      const std::string text = s.get<std::string>();
      const auto eq = text.find('=');
      info.settings.emplace_back(text.substr(0, eq),
                                 eq == std::string::npos ? std::string() : text.substr(eq + 1));
    }
    const auto figures = record::read_figures(run_dir + "/" + info.directory + "/figures.csv");
    summary.figures.insert(summary.figures.end(), figures.begin(), figures.end());
    summary.variants.push_back(std::move(info));
  }
  record::write_figures(run_dir + "/figures.csv", summary.figures);
  record::write_variants(run_dir, summary.variants);
  if (plots) {
    summary.plots = record::draw_plots("replay_plots.py", run_dir);
  } else {
    summary.plots = {
        record::PlotOutcome::Status::skipped,
        "plots not drawn (--no-plots); `flipper replay plot " + run_dir + "` draws them",
        {}};
  }
  const char* status[] = {"drawn", "skipped", "failed"};
  manifest["plots"] = {{"status", status[static_cast<int>(summary.plots.status)]},
                       {"message", summary.plots.message},
                       {"versions", summary.plots.versions}};
  if (!manifest.contains("finished")) manifest["finished"] = record::utc_now();
  manifest["status"] = summary.failed.empty() ? "complete" : finished > 0 ? "partial" : "failed";
  summary.status = manifest["status"].get<std::string>();
  write_report(run_dir, manifest, summary.variants, summary.figures);
  record::write_manifest(run_dir, manifest);
  record::mark_latest(run_dir);
  return summary;
}

}  // namespace flipper::replay
