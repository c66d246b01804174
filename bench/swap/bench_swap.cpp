// bench_swap [experiment.yaml]: runs configs/experiments/swap.yaml (default) and writes its
// Markdown table. For each world, random (start, goal) tasks that the reference planner solves;
// for each pair: success rate, path length / optimum (mean and worst), median planning time.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

namespace fs = std::filesystem;
using namespace flipper;

namespace {

struct Task {
  sdk::Cell start, goal;
  std::size_t optimum;  // reference path length
};

sdk::Params to_params(const YAML::Node& node) {
  std::map<std::string, sdk::ParamValue> values;
  if (!node) return sdk::Params(values);
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& v = kv.second;
    std::int64_t i;
    double d;
    bool b;
    if (YAML::convert<std::int64_t>::decode(v, i))
      values[key] = i;
    else if (YAML::convert<double>::decode(v, d))
      values[key] = d;
    else if (YAML::convert<bool>::decode(v, b))
      values[key] = b;
    else
      values[key] = v.as<std::string>();
  }
  return sdk::Params(values);
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

std::string params_text(const YAML::Node& node) {
  std::string s;
  if (node)
    for (const auto& kv : node)
      s += (s.empty() ? "" : ", ") + kv.first.as<std::string>() + "=" + kv.second.as<std::string>();
  return s.empty() ? "defaults" : s;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path config =
      argc > 1 ? fs::path(argv[1]) : fs::path(FLIPPER_SOURCE_DIR) / "configs/experiments/swap.yaml";
  const YAML::Node exp = YAML::LoadFile(config.string());
  const fs::path base = config.parent_path();
  const auto seed = exp["seed"].as<std::uint32_t>(1);
  const auto task_count = exp["tasks"].as<int>(40);
  const auto reps = exp["repetitions"].as<int>(5);
  auto reference =
      testsupport::load_plugin<sdk::Planner>(exp["reference"].as<std::string>("astar"));

  // Worlds and their tasks.
  std::map<std::string, sdk::WorldState> worlds;
  std::map<std::string, std::vector<Task>> tasks;
  for (const auto& kv : exp["worlds"]) {
    const std::string name = kv.first.as<std::string>();
    const YAML::Node& w = kv.second;
    auto plugin =
        testsupport::load_plugin<sdk::World>(w["plugin"].as<std::string>(), to_params(w["params"]));
    const fs::path file = base / w["file"].as<std::string>();
    worlds[name] = plugin->load(read_file(file), file.parent_path().string());
    const sdk::Geometry& g = *worlds[name].geometry;
    const sdk::Area& free = g.free_cells();
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
    for (int attempts = 0;
         static_cast<int>(tasks[name].size()) < task_count && attempts < 100 * task_count;
         ++attempts) {
      const sdk::Cell s = free[pick(rng)], t = free[pick(rng)];
      if (s == t) continue;
      const sdk::Area goal{t};
      const auto r = reference->plan(g, {s, &goal, nullptr}, sdk::StopCondition{});
      if (r.status == sdk::PlanStatus::found) tasks[name].push_back({s, t, r.path.size()});
    }
  }

  std::ostringstream table;
  table << "| world | planner | params | tasks | success | length / optimum (mean) | (worst) | "
           "median plan time (ms) | max (ms) |\n";
  table << "|---|---|---|---|---|---|---|---|---|\n";
  std::fputs(table.str().c_str(), stdout);  // the header first, so the rows printed below read
  std::fflush(stdout);
  for (const auto& pair : exp["pairs"]) {
    const std::string wname = pair["world"].as<std::string>();
    const std::string pname = pair["planner"].as<std::string>();
    auto planner = testsupport::load_plugin<sdk::Planner>(pname, to_params(pair["params"]));
    const sdk::WorldState& w = worlds.at(wname);
    std::size_t ok = 0;
    std::vector<double> ratios, times;
    for (const Task& t : tasks[wname]) {
      const sdk::Area goal{t.goal};
      std::vector<double> rep_ms;
      sdk::PathResult r;
      for (int k = 0; k < reps; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        r = planner->plan(*w.geometry, {t.start, &goal, nullptr}, sdk::StopCondition{});
        rep_ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
      }
      times.push_back(median(rep_ms));
      if (r.status != sdk::PlanStatus::found) continue;
      ++ok;
      ratios.push_back(static_cast<double>(r.path.size()) / static_cast<double>(t.optimum));
    }
    double mean = 0;
    for (double x : ratios) mean += x;
    mean = ratios.empty() ? 0 : mean / static_cast<double>(ratios.size());
    const double worst = ratios.empty() ? 0 : *std::max_element(ratios.begin(), ratios.end());
    const double tmax = times.empty() ? 0 : *std::max_element(times.begin(), times.end());
    char line[512];
    std::snprintf(line, sizeof line,
                  "| %s | %s | %s | %zu | %.0f%% | %.3f | %.3f | %.3f | %.3f |\n", wname.c_str(),
                  pname.c_str(), params_text(pair["params"]).c_str(), tasks[wname].size(),
                  tasks[wname].empty()
                      ? 0.0
                      : 100.0 * static_cast<double>(ok) / static_cast<double>(tasks[wname].size()),
                  mean, worst, median(times), tmax);
    table << line;
    std::fputs(line, stdout);
    std::fflush(stdout);
  }

  // Written under out/ (never a tracked file); the README quotes a measured copy.
  const fs::path out = base / exp["output"].as<std::string>("../../out/bench/swap-results.md");
  fs::create_directories(out.parent_path());
  std::ofstream md(out);
  md << "# Swap benchmark: worlds x planners\n\n"
     << "Generated by `build/bench/bench_swap` from `configs/experiments/swap.yaml` (seed " << seed
     << ", " << task_count << " random start/goal tasks per world that astar connects, " << reps
     << " repetitions per task, median time per task; the table gives the median over tasks). "
     << "Worlds: grid2d = `configs/worlds/study2018.json`, octomap3d = "
        "`configs/worlds/two-floors.json`. "
     << "Length is the number of cell steps relative to astar's shortest path on the same task.\n\n"
     << table.str();
  std::printf("wrote %s\n", out.string().c_str());
  return 0;
}
