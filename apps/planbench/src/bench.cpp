// Running a planner benchmark into a run folder (docs/planners.md §5).
#include "flipper/planbench/bench.hpp"

#include <stdlib.h>
#include <algorithm>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

#include "assemble.hpp"
#include "flipper/kernel/loader.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/planbench/measure.hpp"
#include "flipper/planbench/shard.hpp"
#include "flipper/planbench/summary.hpp"
#include "flipper/planbench/tasks.hpp"
#include "flipper/record/compare.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/out_file.hpp"
#include "flipper/record/processes.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/config_schema.hpp"

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
  int kill_after_s = 0;  ///< the experiment's wall-clock backstop of one task
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
    return wiring::load_config(config_.empty() ? std::nullopt : std::optional(config_), all);
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
  LoadedWorld out{&w, kernel::load_world_file(rt, config.get(kernel::keys::kWorldFile)), {}};
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
               {},
               e.kill_after_s};
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

std::string read_cell_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A cell in its child process, its tasks `tasks` (all, or a shard's) from position `first` on:
// each task's row appended to cells/<i>.csv as soon as it is measured, so a crash or a hang
// loses that task only. Each task gets the whole wall-clock backstop (processes.hpp).
int run_cell(const std::string& dir, std::size_t i, std::size_t first, const Cell& cell,
             const LoadedWorld& world, const std::vector<std::size_t>& tasks) {
  std::ofstream out(dir + "/" + std::to_string(i) + ".csv", std::ios::app);
  for (std::size_t k = first; k < tasks.size(); ++k) {
    record::restart_backstop();
    const auto rows =
        measure_cell(cell.spec, *world.state.geometry, cell.planner, {world.tasks[tasks[k]]});
    for (const auto& row : rows) out << record::csv_line(row_fields(row)) << "\n";
    out.flush();
    if (!out)
      throw sdk::Error(sdk::codes::kWriteFailed,
                       "cannot write the rows of cell " + std::to_string(i) + " in '" + dir + "'");
  }
  return 0;
}

std::size_t count_lines(const std::string& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// The rows a cell wrote before an interruption: complete lines only (a line cut short is
// removed, and its task runs again).
std::size_t complete_rows(const std::string& path) {
  const std::string text = read_cell_file(path);
  const std::size_t end = text.rfind('\n');
  const std::string kept = end == std::string::npos ? std::string() : text.substr(0, end + 1);
  if (kept.size() != text.size()) {
    std::ofstream out(path, std::ios::trunc);
    out << kept;
    if (!out) throw sdk::Error(sdk::codes::kWriteFailed, "cannot write '" + path + "'");
  }
  return static_cast<std::size_t>(std::count(kept.begin(), kept.end(), '\n'));
}

// The row of a task whose process died (a crash, the backstop, an error outside plan()).
RunRow failed_row(const Cell& cell, const LoadedWorld& world, std::size_t t,
                  const record::ChildExit& exit) {
  const Task& task = world.tasks[t];
  const int dims = world.state.geometry->dims();
  RunRow row;
  row.world = cell.spec.world;
  row.planner = cell.spec.planner;
  row.plugin = cell.spec.plugin;
  row.seed = cell.spec.seed;
  row.task = task.name;
  row.start = sdk::to_string(task.start, dims);
  row.goal = sdk::to_string(task.goal, dims);
  row.shortest = task.shortest;
  row.status = exit.kind();
  row.cause = exit.backstop ? "killed after " + std::to_string(cell.kill_after_s) + " s"
              : exit.signal ? record::signal_name(exit.signal)
                            : exit.message;
  return row;
}

// A row without its measured fields (nothing was measured for a task whose process died).
std::string unmeasured_line(const RunRow& row) {
  auto fields = row_fields(row);
  const auto& columns = run_columns();
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (is_measured_column(columns[c]) || columns[c] == "turns" || columns[c] == "expansions")
      fields[c].clear();
  return record::csv_line(fields);
}

// Runs every cell in its own process, `jobs` at once: cell i's tasks `tasks[i]` (all, or a
// shard's) from position start[i] on. A cell whose process dies gets a row for the task it died
// in (its cause), and its later tasks run in a new process (as a microkernel restarts a crashed
// driver): one crash costs one task. Returns the failures for the manifest.
nlohmann::json run_cells(const std::string& cell_dir, const std::vector<Cell>& cells,
                         const std::vector<LoadedWorld>& worlds,
                         const std::vector<std::vector<std::size_t>>& tasks,
                         const BenchOptions& options, int kill_after_s,
                         const std::vector<std::size_t>& start) {
  std::vector<std::pair<std::pair<std::size_t, std::size_t>, nlohmann::json>> lost;
  std::vector<std::pair<std::size_t, std::size_t>> work;  // (cell, first task)
  std::size_t done = 0;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (start[i] < tasks[i].size())
      work.emplace_back(i, start[i]);
    else
      ++done;  // finished before an interruption (resume)
  record::IsolationOptions isolation;
  isolation.jobs = options.jobs;
  isolation.wall_backstop_s = kill_after_s;
  while (!work.empty()) {
    isolation.on_exit = [&](std::size_t k, const record::ChildExit& exit) {
      const std::size_t i = work[k].first;
      // A cell is done when its process ends well or dies on its last task.
      const bool more = !exit.ok() && count_lines(cell_dir + "/" + std::to_string(i) + ".csv") + 1 <
                                          tasks[i].size();
      if (!more && options.progress) options.progress(++done, cells.size());
    };
    const auto exits = record::run_isolated(work.size(), isolation, [&](std::size_t k) {
      const auto [i, first] = work[k];
      return run_cell(cell_dir, i, first, cells[i], worlds[cells[i].world], tasks[i]);
    });
    std::vector<std::pair<std::size_t, std::size_t>> again;
    for (std::size_t k = 0; k < exits.size(); ++k) {
      if (exits[k].ok()) continue;
      const std::size_t i = work[k].first;
      const Cell& cell = cells[i];
      const LoadedWorld& world = worlds[cell.world];
      const std::string rows_file = cell_dir + "/" + std::to_string(i) + ".csv";
      const std::size_t k_died = count_lines(rows_file);  // the position of the task it died in
      const std::size_t t = k_died < tasks[i].size() ? tasks[i][k_died] : world.tasks.size();
      nlohmann::json failure = {{"world", cell.spec.world},   {"planner", cell.spec.planner},
                                {"plugin", cell.spec.plugin}, {"seed", cell.spec.seed},
                                {"status", exits[k].kind()},  {"cause", exits[k].describe()}};
      if (t < world.tasks.size()) {
        failure["task"] = world.tasks[t].name;
        std::ofstream out(rows_file, std::ios::app);
        out << unmeasured_line(failed_row(cell, world, t, exits[k])) << "\n";
        out.flush();
        if (!out) throw sdk::Error(sdk::codes::kWriteFailed, "cannot write '" + rows_file + "'");
        if (k_died + 1 < tasks[i].size()) again.emplace_back(i, k_died + 1);
      }
      // Kept on disk at once, so a resumed run still names it.
      std::ofstream log(cell_dir + "/failed.jsonl", std::ios::app);
      log << nlohmann::json{{"cell_index", i}, {"task_index", t}, {"failure", failure}}.dump()
          << "\n";
      log.flush();
      if (!log) throw sdk::Error(sdk::codes::kWriteFailed, "cannot write '" + cell_dir + "'");
    }
    work = std::move(again);
  }
  std::ifstream log(cell_dir + "/failed.jsonl");
  for (std::string line; std::getline(log, line);) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;  // a line cut by an interruption
    lost.emplace_back(std::make_pair(j.at("cell_index").get<std::size_t>(),
                                     j.at("task_index").get<std::size_t>()),
                      j.at("failure"));
  }
  // In cell and task order, whatever the order the processes died in.
  std::stable_sort(lost.begin(), lost.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  nlohmann::json failures = nlohmann::json::array();
  for (auto& [where, failure] : lost) failures.push_back(std::move(failure));
  return failures;
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

}  // namespace

BenchResult run_bench(const BenchExperiment& e, const BenchOptions& options) {
  if (options.out.empty()) throw sdk::Error(sdk::codes::kBadRequest, "--out PARENT is required");
  const Settings settings(e, options);
  std::string started = record::utc_now();
  const std::string load = detail::load_text();
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
  // A plugin that hides a same-named one (an out-of-tree astar before the in-tree one) is said
  // at once, and flagged in the manifest (plugins[].origin.shadows).
  std::set<std::string> notes;
  for (const auto& c : cell_list)
    for (const auto& note : record::shadow_notes(c["plugins"])) notes.insert(note);
  for (const auto& note : notes) std::cerr << "flipper bench planners: note: " << note << "\n";
  for (const auto& w : worlds) {
    inputs.push_back(record::file_json("world " + w.spec->name, w.spec->file));
    const TaskSource& t = w.spec->tasks ? *w.spec->tasks : e.tasks;
    if (!t.file.empty()) inputs.push_back(record::file_json("tasks " + w.spec->name, t.file));
  }

  const std::string stem = (e.file.empty() ? "planners" : fs::path(e.file).stem().string()) +
                           (options.shard ? "-shard" + std::to_string(options.shard->index) + "of" +
                                                std::to_string(options.shard->count)
                                          : std::string());
  // The plans this process runs: every task of every cell, or a shard's (shard.hpp).
  std::vector<std::size_t> tasks_per_cell;
  tasks_per_cell.reserve(cells.size());
  for (const auto& c : cells) tasks_per_cell.push_back(worlds[c.world].tasks.size());
  const auto tasks = shard_tasks(tasks_per_cell, options.shard.value_or(record::Shard{}));
  const nlohmann::json shard_json = options.shard ? nlohmann::json{{"index", options.shard->index},
                                                                   {"count", options.shard->count}}
                                                  : nlohmann::json();
  BenchResult result;
  result.cells = cells.size();
  std::vector<std::size_t> start(cells.size(), 0);
  if (options.resume.empty()) {
    result.run_dir = record::create_run_folder(options.out, stem);
    fs::create_directories(result.run_dir + "/cells");
    // What `bench planners resume` needs when the run is interrupted (docs/planners.md §5).
    record::write_manifest(
        result.run_dir,
        {{"kind", "planner-benchmark"},
         {"status", "running"},
         {"shard", shard_json},
         {"started", started},
         {"options",
          {{"config", options.config}, {"overrides", options.overrides}, {"plots", options.plots}}},
         {"experiment", experiment_json(e)},
         {"inputs", inputs}});
  } else {
    result.run_dir = options.resume;
    started = record::read_manifest(result.run_dir).value("started", started);
    for (std::size_t i = 0; i < cells.size(); ++i)
      start[i] = complete_rows(result.run_dir + "/cells/" + std::to_string(i) + ".csv");
  }
  const std::string cell_dir = result.run_dir + "/cells";
  const nlohmann::json failures =
      run_cells(cell_dir, cells, worlds, tasks, options, e.kill_after_s, start);
  result.failures = failures.size();

  record::OutFile runs_out(result.run_dir + "/runs.csv");
  runs_out << record::csv_line(run_columns()) << "\n";
  for (std::size_t i = 0; i < cells.size(); ++i)
    runs_out << read_cell_file(cell_dir + "/" + std::to_string(i) + ".csv");
  runs_out.close();
  fs::remove_all(cell_dir);
  write_tasks(result.run_dir + "/tasks.csv", worlds);

  const nlohmann::json host = record::host_json();
  detail::ReportHead head{e.name,
                          e.file,
                          e.worlds.size(),
                          e.planners.size(),
                          cells.size(),
                          e.repetitions,
                          detail::measured_on(host, load),
                          ""};
  if (options.shard)
    head.shard_note = "Shard " + std::to_string(options.shard->index) + " of " +
                      std::to_string(options.shard->count) +
                      ": the plans whose row r of the whole run's runs.csv has r mod " +
                      std::to_string(options.shard->count) + " = " +
                      std::to_string(options.shard->index) +
                      "; `flipper bench planners merge` joins the shards (docs/planners.md §5, "
                      "\"Shards\").\n\n";
  const BenchResult assembled =
      detail::assemble_bench(result.run_dir, head, failures, options.plots);
  result.runs = assembled.runs;
  result.plots = assembled.plots;
  const std::string status = assembled.status;
  result.status = status;
  const char* plot_status[] = {"drawn", "skipped", "failed"};
  record::write_manifest(
      result.run_dir,
      {{"kind", "planner-benchmark"},
       {"status", status},
       {"shard", shard_json},
       {"failed", failures},
       {"build", record::build_json()},
       {"source", record::source_json()},
       {"plots",
        {{"status", options.plots ? plot_status[static_cast<int>(result.plots.status)] : "skipped"},
         {"versions", result.plots.versions}}},
       {"command", record::command_json()},
       {"host", host},
       {"load_average", load},
       {"jobs", options.jobs},
       {"started", started},
       {"finished", record::utc_now()},
       {"experiment", experiment_json(e)},
       {"options",
        {{"config", options.config}, {"overrides", options.overrides}, {"plots", options.plots}}},
       {"inputs", inputs},
       {"cells", cell_list}});
  record::mark_latest(result.run_dir);
  return result;
}

namespace {

// A recorded benchmark run and what re-running it needs: its manifest, with every input checked
// against the checksum it had (the rows came from those files), and the options it ran with.
nlohmann::json recorded_run(const std::string& run_dir, const std::string& what) {
  nlohmann::json m = record::read_manifest(run_dir);
  if (m.value("kind", std::string()) != "planner-benchmark")
    throw sdk::Error(sdk::codes::kBadRequest, "'" + run_dir + "' is not a planner benchmark run");
  if (!m.contains("options"))
    throw sdk::Error(
        sdk::codes::kBadRequest,
        "'" + run_dir + "' records no options (made by an older flipper): cannot " + what + " it");
  for (const auto& f : m.value("inputs", nlohmann::json::array())) {
    const std::string path = f.at("path").get<std::string>();
    std::error_code ec;
    const std::string now =
        fs::is_regular_file(path, ec) ? record::file_json("", path).value("sha256", "") : "";
    if (now != f.value("sha256", std::string()))
      throw sdk::Error(sdk::codes::kBadRequest,
                       "cannot " + what + " '" + run_dir + "': " + f.value("role", std::string()) +
                           " '" + path + "' " + (now.empty() ? "is gone" : "changed") +
                           " since the run started (recorded sha256 " +
                           f.value("sha256", std::string()).substr(0, 12) + "…)");
  }
  return m;
}

BenchOptions recorded_options(const nlohmann::json& m, const std::string& out, int jobs,
                              bool plots) {
  const nlohmann::json o = m.value("options", nlohmann::json::object());
  BenchOptions options;
  options.config = o.value("config", std::string());
  options.overrides = o.value("overrides", std::vector<std::string>());
  options.out = out;
  options.jobs = jobs;
  options.plots = plots;
  const nlohmann::json shard = m.value("shard", nlohmann::json());
  if (shard.is_object())
    options.shard = record::Shard{shard.at("index").get<int>(), shard.at("count").get<int>()};
  return options;
}

}  // namespace

BenchResult resume_bench(const std::string& run_dir, int jobs, bool plots) {
  const nlohmann::json m = recorded_run(run_dir, "resume");
  if (m.value("status", std::string()) != "running" || !fs::is_directory(run_dir + "/cells"))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "'" + run_dir + "' finished (status " + m.value("status", std::string("?")) +
                         "): only an interrupted run (status running) is resumed");
  BenchOptions options =
      recorded_options(m, fs::path(run_dir).lexically_normal().parent_path().string(), jobs, plots);
  options.resume = run_dir;
  return run_bench(load_bench_experiment(m.at("experiment").at("file").get<std::string>()),
                   options);
}

BenchCheck check_bench(const std::string& run_dir, int jobs, const std::string& keep_under) {
  const nlohmann::json m = recorded_run(run_dir, "check");
  if (m.value("status", std::string()) == "running")
    throw sdk::Error(sdk::codes::kBadRequest,
                     "'" + run_dir + "' has not finished (status running): resume it first");
  std::string parent = keep_under;
  if (parent.empty()) {
    std::string pattern = (fs::temp_directory_path() / "flipper-check-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw sdk::Error(sdk::codes::kWriteFailed, "cannot make a temporary folder for the check");
    parent = pattern;
  }
  BenchCheck out;
  const BenchResult again =
      run_bench(load_bench_experiment(m.at("experiment").at("file").get<std::string>()),
                recorded_options(m, parent, jobs, false));
  record::ComparisonCounts counts;
  out.text = record::compare_runs(record::read_run_figures(run_dir),
                                  record::read_run_figures(again.run_dir), false, &counts);
  out.compared = counts.compared;
  out.differing = counts.differing;
  out.rerun = keep_under.empty() ? std::string() : again.run_dir;
  if (keep_under.empty()) {
    std::error_code ec;
    fs::remove_all(parent, ec);
  }
  return out;
}

}  // namespace flipper::planbench
