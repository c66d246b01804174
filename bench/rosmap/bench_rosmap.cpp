// ROS-map benchmark (docs/ros-maps.md, "Size and speed"): for depot, tb3_sandbox (data/ros-maps)
// and a synthetic 1414 x 1414 map (2.0 M cells, written to a temporary folder), the median CPU
// time of loading the world (YAML + PGM -> free mask with inflation -> rooms) and of planning
// to each region with the astar planner, next to the budgets a request has: a `world` request
// within session.deadline_ms (5000 ms), a plan within execution.deadline_ms (2000 ms) and the
// path within execution.action_budget (100000 actions). CPU time of this thread, because the
// machine is shared.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

using namespace flipper;

namespace {

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

constexpr double kLoadBudgetMs = 5000;    // session.deadline_ms
constexpr double kPlanBudgetMs = 2000;    // execution.deadline_ms
constexpr double kActionBudget = 100000;  // execution.action_budget

int met = 0, measured = 0;

void row(const std::string& what, double ms, double target, const std::string& unit) {
  ++measured;
  const bool ok = ms <= target;
  met += ok ? 1 : 0;
  std::printf("  %-44s %10.1f %-7s target <= %-8.0f %s\n", what.c_str(), ms, unit.c_str(), target,
              ok ? "met" : "MISSED");
}

void bench_map(const std::string& name, const std::string& world_file, const std::string& dir,
               double radius, int runs) {
  sdk::Params p;
  p.set("inflation_radius", radius);
  const auto world = testsupport::load_plugin<sdk::World>("ros_map", p);
  const auto planner = testsupport::load_plugin<sdk::Planner>("astar");
  const std::string text = read(world_file);
  std::vector<double> loads;
  sdk::WorldState s;
  for (int i = 0; i < runs; ++i) {
    const double t0 = cpu_ms();
    s = world->load(text, dir);
    loads.push_back(cpu_ms() - t0);
  }
  const auto& g = *s.geometry;
  std::printf("%s: %zu x %zu = %zu cells (%zu free), inflation %.3f m\n", name.c_str(), g.size_x(),
              g.size_y(), g.cell_count(), g.free_cells().size(), radius);
  row("load (median of " + std::to_string(runs) + ")", median(loads), kLoadBudgetMs, "ms");
  for (const auto& [room, area] : *s.rooms) {
    std::vector<double> plans;
    std::size_t steps = 0;
    for (int i = 0; i < runs; ++i) {
      const double t0 = cpu_ms();
      const auto r = planner->plan(g, {s.robot, &area, nullptr}, sdk::StopCondition{});
      plans.push_back(cpu_ms() - t0);
      if (r.status != sdk::PlanStatus::found)
        std::printf("  unexpected: no path to %s\n", room.c_str());
      steps = r.path.size();
    }
    row("plan to " + room + " (median)", median(plans), kPlanBudgetMs, "ms");
    row("  its path, in actions", static_cast<double>(steps), kActionBudget, "steps");
  }
}

// 1414 x 1414 free cells with a wall every 100 cells (one door per wall, alternating ends) and
// 2000 random 3 x 3 pillars: long corridors, so a plan across explores most of the map.
std::string write_synthetic(const std::filesystem::path& dir) {
  constexpr int n = 1414;
  std::vector<unsigned char> px(static_cast<std::size_t>(n) * n, 254);
  for (int wall = 100; wall < n; wall += 100) {
    const bool door_low = (wall / 100) % 2 == 0;
    for (int row = 0; row < n; ++row)
      if (door_low ? row < n - 40 : row >= 40) px[static_cast<std::size_t>(row) * n + wall] = 0;
  }
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> at(1, n - 5);
  for (int i = 0; i < 2000; ++i) {
    const int x = at(rng), y = at(rng);
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx) px[static_cast<std::size_t>(y + dy) * n + x + dx] = 0;
  }
  // The start and goal corners stay free.
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      px[static_cast<std::size_t>(n - 1 - y) * n + x] = 254;    // bottom-left
      px[static_cast<std::size_t>(y) * n + (n - 1 - x)] = 254;  // top-right
    }
  std::ofstream pgm(dir / "synthetic.pgm", std::ios::binary);
  pgm << "P5\n" << n << " " << n << "\n255\n";
  pgm.write(reinterpret_cast<const char*>(px.data()), static_cast<std::streamsize>(px.size()));
  std::ofstream(dir / "synthetic.yaml")
      << "image: synthetic.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
         "occupied_thresh: 0.65\nfree_thresh: 0.25\n";
  const std::string world =
      R"({"map": "synthetic.yaml", "start": {"x": 0.2, "y": 0.2},
 "regions": [{"room": "room1", "name": "far", "polygon": [[70.0, 70.0], [70.7, 70.0], [70.7, 70.7], [70.0, 70.7]]}]})";
  std::ofstream(dir / "synthetic.world.json") << world;
  return (dir / "synthetic.world.json").string();
}

}  // namespace

int main() {
  const std::string maps = std::string(FLIPPER_SOURCE_DIR) + "/data/ros-maps";
  std::printf("ros_map: load and plan, CPU ms of this thread (medians)\n");
  bench_map("depot", maps + "/depot.world.json", maps, 0.2, 7);
  bench_map("tb3_sandbox", maps + "/tb3_sandbox.world.json", maps, 0.105, 7);
  const auto tmp = std::filesystem::temp_directory_path() /
                   ("flipper-bench-rosmap-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  const std::string synthetic = write_synthetic(tmp);
  bench_map("synthetic 2M", synthetic, tmp.string(), 0.2, 3);
  std::filesystem::remove_all(tmp);
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  std::printf("peak RSS %.1f MiB\n", static_cast<double>(u.ru_maxrss) / 1024);
  std::printf("%d of %d targets met\n", met, measured);
  return met == measured ? 0 : 1;
}
