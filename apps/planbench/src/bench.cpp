// Running a planner benchmark into a run folder (docs/planners.md §5).
#include "flipper/planbench/bench.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/kernel/loader.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/planbench/measure.hpp"
#include "flipper/planbench/summary.hpp"
#include "flipper/planbench/tasks.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/out_file.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::planbench {
namespace fs = std::filesystem;
namespace {

struct LoadedWorld {
  const WorldSpec* spec = nullptr;
  sdk::WorldState state;
  std::vector<Task> tasks;
};

struct Cell {
  CellSpec spec;
  std::size_t world = 0;  ///< index into the loaded worlds
  kernel::Config config;
  kernel::PluginRef<sdk::Planner> planner;
};

std::vector<std::string> world_sets(const WorldSpec& w) {
  return {"world.plugin=" + w.plugin, "world.file=" + w.file,
          "world.params=" + (w.params.empty() ? std::string("null") : w.params)};
}

std::vector<std::string> planner_sets(const PlannerSpec& p) {
  return {"planner.plugin=" + p.plugin,
          "planner.params=" + (p.params.empty() ? std::string("null") : p.params)};
}

// Whether a planner's params (as written in the experiment) give a seed of their own.
bool params_name_seed(const std::string& flow) {
  return flow.find("seed:") != std::string::npos;
}

class Settings {
 public:
  Settings(const BenchExperiment& e, const BenchOptions& o) : options_(o) {
    config_ = o.config.empty() ? e.config : o.config;
    sets_ = e.sets;
    if (!e.plugin_paths.empty()) {
      std::string list;
      for (const auto& p : e.plugin_paths) list += (list.empty() ? "" : ", ") + p;
      sets_.push_back("plugin_paths=[" + list + "]");
    }
  }
  kernel::Config config(const std::vector<std::string>& extra) const {
    std::vector<std::string> all = sets_;
    all.insert(all.end(), extra.begin(), extra.end());
    all.insert(all.end(), options_.overrides.begin(), options_.overrides.end());
    return kernel::Config::load(config_.empty() ? std::nullopt : std::optional(config_), all);
  }

 private:
  const BenchOptions& options_;
  std::string config_;
  std::vector<std::string> sets_;
};

LoadedWorld load_world_unlabelled(const Settings& settings, const BenchExperiment& e,
                                  const WorldSpec& w) {
  const kernel::Config config = settings.config(world_sets(w));
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  kernel::Runtime rt(config);
  rt.world = loader.create<sdk::World>(config, "world");
  LoadedWorld out{&w, kernel::load_world_file(rt, config.get_path("world.file")), {}};
  if (!out.state.geometry)
    throw sdk::Error(sdk::codes::kBadWorld, "plugin '" + w.plugin + "' gave no geometry");
  out.tasks = tasks_for(w.tasks ? *w.tasks : e.tasks, *out.state.geometry);
  if (out.tasks.empty())
    throw sdk::Error(sdk::codes::kBadConfig, "no task (no two free cells the oracle connects)");
  return out;
}

// The same error, its message prefixed with what it is about ("planner 'rrt' on world 'maze'").
template <class F>
auto about(const std::string& what, F&& f) {
  try {
    return f();
  } catch (const sdk::Error& e) {
    throw sdk::Error(e.code(), what + ": " + e.what());
  }
}

LoadedWorld load_world(const Settings& settings, const BenchExperiment& e, const WorldSpec& w) {
  return about("world '" + w.name + "'", [&] { return load_world_unlabelled(settings, e, w); });
}

// Every cell's planner, loaded and checked against its world before anything runs.
std::vector<Cell> plan_cells(const Settings& settings, const BenchExperiment& e,
                             const std::vector<LoadedWorld>& worlds) {
  std::vector<Cell> cells;
  for (std::size_t wi = 0; wi < worlds.size(); ++wi) {
    const WorldSpec& w = *worlds[wi].spec;
    const int dims = worlds[wi].state.geometry->dims();
    for (const PlannerSpec& p : e.planners) {
      std::vector<std::string> sets = world_sets(w);
      for (auto& s : planner_sets(p)) sets.push_back(std::move(s));
      const std::string what = "planner '" + p.name + "' on world '" + w.name + "'";
      const kernel::Config base = about(what, [&] { return settings.config(sets); });
      const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(base));
      const bool seeded = !params_name_seed(p.params) && about(what, [&] {
        return loader.open(base.plugin_name("planner"), sdk::PluginKind::planner)
                   .schema()
                   .find("seed") != nullptr;
      });
      std::vector<std::string> seeds;
      if (seeded)
        for (const auto s : e.seeds) seeds.push_back(std::to_string(s));
      else
        seeds.emplace_back();
      for (const auto& seed : seeds) {
        std::vector<std::string> cell_sets = sets;
        if (!seed.empty()) cell_sets.push_back("planner.params.seed=" + seed);
        Cell c{{w.name, p.name, base.plugin_name("planner"), seed, e.repetitions, e.deadline_ms,
                e.cpu_budget_ms},
               wi,
               about(what, [&] { return settings.config(cell_sets); }),
               {}};
        c.planner = about(what, [&] { return loader.create<sdk::Planner>(c.config, "planner"); });
        const auto traits =
            c.planner.call("traits", [](const sdk::Planner& pl) { return pl.traits(); });
        if ((dims == 3 && !traits.supports_3d) || (dims == 2 && !traits.supports_2d))
          throw sdk::Error(sdk::codes::kBadConfig, "planner '" + p.name + "' (plugin '" +
                                                       c.spec.plugin + "') does not support the " +
                                                       std::to_string(dims) + "-D world '" +
                                                       w.name + "'; leave that pair out");
        cells.push_back(std::move(c));
      }
    }
  }
  return cells;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A cell in its child process: rows to cells/<i>.csv, or its error to cells/<i>.err.
int run_cell(const std::string& dir, std::size_t i, const Cell& cell, const LoadedWorld& world) {
  const std::string stem = dir + "/" + std::to_string(i);
  try {
    const auto rows = measure_cell(cell.spec, *world.state.geometry, cell.planner, world.tasks);
    record::OutFile out(stem + ".csv");
    for (const auto& row : rows) out << record::csv_line(row_fields(row)) << "\n";
    out.close();
    return 0;
  } catch (const sdk::Error& e) {
    std::ofstream(stem + ".err") << e.code() << "\n" << e.what();
  } catch (const std::exception& e) {
    std::ofstream(stem + ".err") << sdk::codes::kInternal << "\n" << e.what();
  }
  return 1;
}

void write_tasks(const std::string& path, const std::vector<LoadedWorld>& worlds) {
  record::OutFile out(path);
  out << "world,task,start,goal,shortest\n";
  for (const auto& w : worlds)
    for (const auto& t : w.tasks) {
      const int dims = w.state.geometry->dims();
      out << record::csv_line({w.spec->name, t.name, sdk::to_string(t.start, dims),
                               sdk::to_string(t.goal, dims),
                               t.shortest ? std::to_string(*t.shortest) : ""})
          << "\n";
    }
  out.close();
}

std::string load_text() {
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 1) return "unknown";
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << load[0];
  return s.str();
}

void write_report(const std::string& run_dir, const BenchExperiment& e,
                  const record::CsvTable& runs, const nlohmann::json& host, const std::string& load,
                  std::size_t cells) {
  record::OutFile out(run_dir + "/report.md");
  out << "# Planner benchmark: " << e.name << "\n\n"
      << "Experiment `" << e.file << "`; " << e.worlds.size() << " worlds × " << e.planners.size()
      << " planners, " << cells << " cells (world × planner × seed), " << runs.rows.size()
      << " plans. Files: `manifest.json` (build, plugins with SHA-256, each cell's config, "
         "inputs), `tasks.csv` (each world's tasks with the oracle's shortest length), "
         "`runs.csv` (one row per plan), `figures.csv`, `variants.csv`, the plots "
         "(`planners.pdf`, `.svg`).\n\n"
      << "## Results (deterministic)\n\n"
      << "Length in steps; length / shortest against a breadth-first oracle over the world's "
         "cells; means over the successful plans, success over all (tasks × seeds). \"Stopped "
         "for time\": plans a time limit ended, not planning failures: `cpu_budget` (the "
         "experiment's cpu_budget_ms of the planning thread's CPU time) or `wall_backstop` (its "
         "deadline_ms of wall time, a runaway guard).\n\n"
      << results_table(runs) << "\n## Timing (measured)\n\n"
      << "Measured on " << host.value("name", std::string("?")) << " (" << host.value("cores", 0)
      << " cores, load " << load
      << " at the start): plan CPU time is the planning thread's CPU time, the median of "
      << e.repetitions
      << " repetition(s) per task; memory is the peak resident set during the plan "
         "(VmHWM, reset before it) and its growth over the resident set before it.\n\n"
      << timing_table(runs);
  out.close();
}

}  // namespace

BenchResult run_bench(const BenchExperiment& e, const BenchOptions& options) {
  if (options.out.empty()) throw sdk::Error(sdk::codes::kBadRequest, "--out PARENT is required");
  const Settings settings(e, options);
  const std::string started = record::utc_now();
  const std::string load = load_text();
  // Everything loads and is checked before a run folder exists.
  std::vector<LoadedWorld> worlds;
  for (const auto& w : e.worlds) worlds.push_back(load_world(settings, e, w));
  const std::vector<Cell> cells = plan_cells(settings, e, worlds);
  nlohmann::json cell_list = nlohmann::json::array(), inputs = nlohmann::json::array();
  for (const auto& c : cells)
    cell_list.push_back({{"world", c.spec.world},
                         {"planner", c.spec.planner},
                         {"seed", c.spec.seed},
                         {"config", record::config_json(c.config)},
                         {"plugins", record::plugins_json(c.config, {"world", "planner"})}});
  if (!e.file.empty()) inputs.push_back(record::file_json("experiment", e.file));
  for (const auto& w : worlds) {
    inputs.push_back(record::file_json("world " + w.spec->name, w.spec->file));
    const TaskSource& t = w.spec->tasks ? *w.spec->tasks : e.tasks;
    if (!t.file.empty()) inputs.push_back(record::file_json("tasks " + w.spec->name, t.file));
  }

  const std::string stem = e.file.empty() ? "planners" : fs::path(e.file).stem().string();
  BenchResult result;
  result.run_dir = record::create_run_folder(options.out, stem);
  result.cells = cells.size();
  const std::string cell_dir = result.run_dir + "/cells";
  fs::create_directories(cell_dir);
  const auto statuses = record::run_in_processes(
      cells.size(), options.jobs,
      [&](std::size_t i) { return run_cell(cell_dir, i, cells[i], worlds[cells[i].world]); },
      nullptr);
  for (std::size_t i = 0; i < statuses.size(); ++i) {
    if (statuses[i] == 0) continue;
    const std::string err = read_text(cell_dir + "/" + std::to_string(i) + ".err");
    const auto nl = err.find('\n');
    const std::string where = "cell " + cells[i].spec.world + " × " + cells[i].spec.planner +
                              (cells[i].spec.seed.empty() ? "" : " seed " + cells[i].spec.seed);
    if (nl != std::string::npos)
      throw sdk::Error(err.substr(0, nl), where + ": " + err.substr(nl + 1));
    if (statuses[i] > 0)
      throw sdk::Error(sdk::codes::kInternal,
                       where + ": its process ended with status " + std::to_string(statuses[i]));
  }

  record::OutFile runs_out(result.run_dir + "/runs.csv");
  runs_out << record::csv_line(run_columns()) << "\n";
  for (std::size_t i = 0; i < cells.size(); ++i)
    runs_out << read_text(cell_dir + "/" + std::to_string(i) + ".csv");
  runs_out.close();
  fs::remove_all(cell_dir);
  write_tasks(result.run_dir + "/tasks.csv", worlds);

  const record::CsvTable runs = record::read_csv(result.run_dir + "/runs.csv");
  result.runs = runs.rows.size();
  const BenchFigures figures = bench_figures(runs);
  record::write_figures(result.run_dir + "/figures.csv", figures.figures);
  record::write_variants(result.run_dir, figures.variants);
  const nlohmann::json host = record::host_json();
  write_report(result.run_dir, e, runs, host, load, cells.size());

  record::write_manifest(result.run_dir, {{"kind", "planner-benchmark"},
                                          {"build", record::build_json()},
                                          {"command", record::command_json()},
                                          {"host", host},
                                          {"load_average", load},
                                          {"jobs", options.jobs},
                                          {"started", started},
                                          {"finished", record::utc_now()},
                                          {"experiment", experiment_json(e)},
                                          {"inputs", inputs},
                                          {"cells", cell_list}});
  if (options.plots) result.plots = record::draw_plots("planner_bench_plots.py", result.run_dir);
  return result;
}

}  // namespace flipper::planbench
