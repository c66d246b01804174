// A benchmark split into shards and merged again (docs/planners.md §5, "Shards").
#include "flipper/planbench/shard.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "assemble.hpp"
#include "flipper/planbench/measure.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/durable_file.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::planbench {
namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::vector<std::size_t>> shard_tasks(const std::vector<std::size_t>& tasks_per_cell,
                                                  const record::Shard& shard) {
  std::vector<std::vector<std::size_t>> out(tasks_per_cell.size());
  std::size_t row = 0;
  for (std::size_t i = 0; i < tasks_per_cell.size(); ++i)
    for (std::size_t t = 0; t < tasks_per_cell[i]; ++t, ++row)
      if (record::in_shard(row, shard)) out[i].push_back(t);
  return out;
}

namespace {

sdk::Error refused(const std::string& why) {
  return sdk::Error(sdk::codes::kBadRequest, why);
}

// The experiment without what names a place on one machine (the file, worlds' and task files,
// plugin folders, the base config): shards run on different machines see it at other paths.
json identity(json experiment) {
  for (const char* key : {"file", "plugin_paths", "config"}) experiment.erase(key);
  for (auto& w : experiment["worlds"]) {
    w.erase("file");
    if (w.contains("tasks")) w["tasks"].erase("file");
  }
  if (experiment.contains("tasks")) experiment["tasks"].erase("file");
  return experiment;
}

// What the shards must agree on beside the experiment: each input's role and checksum, the
// --set lines, and the cells (world, planner, seed) in order.
json agreement(const json& m) {
  json inputs = json::array(), cells = json::array();
  for (const auto& f : m.value("inputs", json::array()))
    inputs.push_back({f.value("role", ""), f.value("sha256", "")});
  for (const auto& c : m.value("cells", json::array()))
    cells.push_back({c.value("world", ""), c.value("planner", ""), c.value("seed", "")});
  return {{"experiment", identity(m.value("experiment", json::object()))},
          {"inputs", inputs},
          {"set", m.value("options", json::object()).value("overrides", json::array())},
          {"cells", cells}};
}

std::string read_shard_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw refused("cannot read '" + path + "'");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct ShardRun {
  std::string dir;
  json manifest;
  record::Shard shard;
  std::string tasks_text;  ///< tasks.csv, byte for byte
  record::CsvTable runs;
};

ShardRun read_shard(const std::string& dir) {
  ShardRun s{dir, {}, {}, {}, {}};
  if (!record::is_run_folder(dir)) throw refused("'" + dir + "' is not a run folder");
  s.manifest = record::read_manifest(dir);
  if (s.manifest.value("kind", std::string()) != "planner-benchmark")
    throw refused("'" + dir + "' is not a planner benchmark run");
  const std::string status = s.manifest.value("status", std::string());
  if (status != "complete" && status != "partial" && status != "failed")
    throw refused("'" + dir + "' has not finished (status " + status +
                  "): resume it first (`flipper bench planners resume`)");
  const json shard = s.manifest.value("shard", json());
  if (!shard.is_object())
    throw refused("'" + dir + "' is not a shard (it ran without --shard I/N)");
  s.shard = {shard.at("index").get<int>(), shard.at("count").get<int>()};
  s.tasks_text = read_shard_file(dir + "/tasks.csv");
  s.runs = record::read_csv(dir + "/runs.csv");
  return s;
}

// The shards, one per index 0..N-1, in index order, each checked against the first.
std::vector<ShardRun> read_shards(const std::vector<std::string>& dirs,
                                  std::vector<std::string>& warnings) {
  if (dirs.empty()) throw refused("no runs to merge");
  std::map<int, ShardRun> by_index;
  const ShardRun first = read_shard(dirs.front());
  const json agreed = agreement(first.manifest);
  for (const auto& dir : dirs) {
    ShardRun s = read_shard(dir);
    const json mine = agreement(s.manifest);
    for (const char* key : {"experiment", "inputs", "set", "cells"})
      if (mine[key] != agreed[key])
        throw refused("'" + dir + "' and '" + first.dir + "' are not shards of one run: their " +
                      (std::string(key) == "set"      ? "--set lines"
                       : std::string(key) == "inputs" ? "input files (checksums)"
                       : std::string(key) == "cells"  ? "cells"
                                                      : "experiments") +
                      " differ");
    if (s.tasks_text != first.tasks_text)
      throw refused("'" + dir + "' and '" + first.dir + "' drew different tasks (tasks.csv)");
    if (s.runs.header != first.runs.header)
      throw refused("'" + dir + "' and '" + first.dir + "' have different runs.csv columns");
    if (s.shard.count != first.shard.count)
      throw refused("'" + dir + "' is a shard of " + std::to_string(s.shard.count) + ", '" +
                    first.dir + "' of " + std::to_string(first.shard.count));
    for (const auto& w : record::provenance_warnings(first.manifest, s.manifest))
      warnings.push_back(dir + " vs " + first.dir + ": " + w);
    const int index = s.shard.index;
    auto [it, fresh] = by_index.emplace(index, std::move(s));
    if (!fresh)
      throw refused("shard " + std::to_string(index) + " is given twice: '" + it->second.dir +
                    "' and '" + dir + "'");
  }
  std::string missing;
  for (int k = 0; k < first.shard.count; ++k)
    if (by_index.count(k) == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (!missing.empty())
    throw refused("shard(s) " + missing + " of " + std::to_string(first.shard.count) + " missing");
  std::vector<ShardRun> out;
  out.reserve(by_index.size());
  for (auto& [index, s] : by_index) out.push_back(std::move(s));
  return out;
}

// Each cell's world, planner, seed and its world's task names (from tasks.csv, in order).
struct Grid {
  std::vector<std::vector<std::string>> cells;  // world, planner, seed
  std::vector<std::vector<std::string>> tasks;  // per cell: its world's task names
};

Grid grid_of(const ShardRun& s) {
  const record::CsvTable tasks = record::parse_csv(s.tasks_text, s.dir + "/tasks.csv");
  const std::size_t world = tasks.column("world", "tasks.csv"),
                    task = tasks.column("task", "tasks.csv");
  std::map<std::string, std::vector<std::string>> names;
  for (const auto& r : tasks.rows) names[r[world]].push_back(r[task]);
  Grid g;
  for (const auto& c : s.manifest.value("cells", json::array())) {
    g.cells.push_back({c.value("world", ""), c.value("planner", ""), c.value("seed", "")});
    g.tasks.push_back(names[c.value("world", "")]);
  }
  return g;
}

bool is_lost(const std::string& status) {
  return status == "plugin_crashed" || status == "crashed" || status == "wall_backstop" ||
         status == "failed";
}

}  // namespace

BenchResult merge_bench(const std::vector<std::string>& runs, const std::string& out, bool plots,
                        std::vector<std::string>& warnings) {
  const std::vector<ShardRun> shards = read_shards(runs, warnings);
  const Grid grid = grid_of(shards.front());
  std::vector<std::size_t> per_cell;
  per_cell.reserve(grid.tasks.size());
  for (const auto& t : grid.tasks) per_cell.push_back(t.size());

  // Every shard's rows are its share of the grid, in grid order: check them, then interleave.
  const auto& header = shards.front().runs.header;
  const std::size_t world = shards.front().runs.column("world", "runs.csv"),
                    planner = shards.front().runs.column("planner", "runs.csv"),
                    seed = shards.front().runs.column("seed", "runs.csv"),
                    task = shards.front().runs.column("task", "runs.csv"),
                    status = shards.front().runs.column("status", "runs.csv");
  std::vector<std::size_t> next(shards.size(), 0);
  std::string text = record::csv_line(header) + "\n";
  std::vector<std::pair<std::size_t, std::size_t>> lost_rows;  // (shard, its row), in grid order
  std::size_t row = 0;
  for (std::size_t i = 0; i < grid.cells.size(); ++i)
    for (std::size_t t = 0; t < per_cell[i]; ++t, ++row) {
      const std::size_t k = row % shards.size();
      const ShardRun& s = shards[k];
      const std::string where = "'" + s.dir + "'";
      if (next[k] >= s.runs.rows.size())
        throw refused(where + " lacks its row for " + grid.cells[i][0] + " × " + grid.cells[i][1] +
                      (grid.cells[i][2].empty() ? "" : " seed " + grid.cells[i][2]) + ", task " +
                      grid.tasks[i][t] + " (is it a shard of this grid?)");
      const auto& r = s.runs.rows[next[k]];
      if (r[world] != grid.cells[i][0] || r[planner] != grid.cells[i][1] ||
          r[seed] != grid.cells[i][2] || r[task] != grid.tasks[i][t])
        throw refused(where + " row " + std::to_string(next[k] + 1) + " is " + r[world] + " × " +
                      r[planner] + " task " + r[task] + " where its share of the grid has " +
                      grid.cells[i][0] + " × " + grid.cells[i][1] + " task " + grid.tasks[i][t]);
      if (is_lost(r[status])) lost_rows.emplace_back(k, next[k]);
      text += record::csv_line(r) + "\n";
      ++next[k];
    }
  for (std::size_t k = 0; k < shards.size(); ++k)
    if (next[k] != shards[k].runs.rows.size())
      throw refused("'" + shards[k].dir + "' has " + std::to_string(shards[k].runs.rows.size()) +
                    " rows, its share of the grid " + std::to_string(next[k]));

  // The lost tasks in grid order: each shard's list is in its own row order already.
  json failures = json::array();
  std::vector<std::size_t> taken(shards.size(), 0);
  std::vector<json> lists;
  lists.reserve(shards.size());
  for (const auto& s : shards) lists.push_back(s.manifest.value("failed", json::array()));
  for (const auto& [k, r] : lost_rows)
    if (taken[k] < lists[k].size()) failures.push_back(lists[k][taken[k]++]);
  for (std::size_t k = 0; k < shards.size(); ++k)
    for (; taken[k] < lists[k].size(); ++taken[k]) failures.push_back(lists[k][taken[k]]);

  const json& first = shards.front().manifest;
  const json experiment = first.value("experiment", json::object());
  const std::string file = experiment.value("file", std::string());
  const std::string stem =
      (file.empty() ? std::string("planners") : fs::path(file).stem().string()) + "-merged";
  const std::string run_dir = record::create_run_folder(out, stem);
  record::write_file_atomically(run_dir + "/runs.csv", text);
  record::write_file_atomically(run_dir + "/tasks.csv", shards.front().tasks_text);

  json merged = json::array();
  std::string started = first.value("started", std::string()), finished, hosts;
  for (const auto& s : shards) {
    const json& m = s.manifest;
    merged.push_back({{"run", fs::absolute(s.dir).lexically_normal().string()},
                      {"shard", m["shard"]},
                      {"status", m["status"]},
                      {"build", m["build"]},
                      {"source", m["source"]},
                      {"host", m["host"]},
                      {"load_average", m["load_average"]},
                      {"jobs", m["jobs"]},
                      {"command", m["command"]},
                      {"started", m["started"]},
                      {"finished", m["finished"]}});
    started = std::min(started, m.value("started", started));
    finished = std::max(finished, m.value("finished", finished));
    hosts += (hosts.empty() ? "" : ", ") + std::string("shard ") + std::to_string(s.shard.index) +
             " on " +
             detail::measured_on(m.value("host", json::object()),
                                 m.value("load_average", std::string("unknown")));
  }
  const detail::ReportHead head{experiment.value("name", std::string()),
                                file,
                                experiment.value("worlds", json::array()).size(),
                                experiment.value("planners", json::array()).size(),
                                grid.cells.size(),
                                experiment.value("repetitions", 1),
                                std::to_string(shards.size()) + " shards merged: " + hosts,
                                ""};
  BenchResult result = detail::assemble_bench(run_dir, head, failures, plots);
  const char* plot_status[] = {"drawn", "skipped", "failed"};
  json manifest = first;
  manifest["status"] = result.status;
  manifest["shard"] = json();
  manifest["failed"] = failures;
  manifest["merged_from"] = merged;
  manifest["started"] = started;
  manifest["finished"] = finished;
  manifest["command"] = record::command_json();
  manifest["plots"] = {
      {"status", plots ? plot_status[static_cast<int>(result.plots.status)] : "skipped"},
      {"versions", result.plots.versions}};
  record::write_manifest(run_dir, manifest);
  record::mark_latest(run_dir);
  return result;
}

}  // namespace flipper::planbench
