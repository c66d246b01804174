// One benchmark cell: plans, checks them against the oracle, and measures their cost
// (docs/planners.md §5).
#include "flipper/planbench/measure.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>

#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/sdk/errors.hpp"
#include "stats.hpp"

namespace flipper::planbench {
namespace {

double thread_cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_nsec) / 1e3;
}

// A field of /proc/self/status in KiB ("VmHWM"), or none.
std::optional<std::int64_t> status_kib(const std::string& field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) {
      std::istringstream value(line.substr(field.size() + 1));
      std::int64_t kib = 0;
      if (value >> kib) return kib;
    }
  return std::nullopt;
}

// Resets the process's peak resident set (VmHWM) to the present one: Linux's
// /proc/self/clear_refs, value 5. False where the kernel does not offer it.
bool reset_peak_rss() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

std::string optional_text(const std::optional<std::size_t>& v) {
  return v ? std::to_string(*v) : std::string();
}

}  // namespace

const std::vector<std::string>& run_columns() {
  static const std::vector<std::string> columns{
      "world",  "planner", "plugin",       "seed",       "task",         "start", "goal",
      "status", "success", "length",       "shortest",   "length_ratio", "turns", "expansions",
      "cpu_us", "wall_us", "peak_rss_kib", "memory_kib", "stopped",      "cause"};
  return columns;
}

bool is_measured_column(const std::string& column) {
  return column == "cpu_us" || column == "wall_us" || column == "peak_rss_kib" ||
         column == "memory_kib";
}

std::vector<std::string> row_fields(const RunRow& r) {
  std::string ratio;
  if (r.success && r.length && r.shortest)
    ratio = *r.shortest == 0 ? "1"
                             : record::exact_number(static_cast<double>(*r.length) /
                                                    static_cast<double>(*r.shortest));
  auto kib = [](const std::optional<std::int64_t>& v) {
    return v ? std::to_string(*v) : std::string();
  };
  return {r.world,
          r.planner,
          r.plugin,
          r.seed,
          r.task,
          r.start,
          r.goal,
          r.status,
          r.success ? "1" : "0",
          optional_text(r.length),
          optional_text(r.shortest),
          ratio,
          std::to_string(r.turns),
          std::to_string(r.expansions),
          record::exact_number(r.cpu_us),
          record::exact_number(r.wall_us),
          kib(r.peak_rss_kib),
          kib(r.memory_kib),
          r.stopped,
          r.cause};
}

std::size_t count_turns(sdk::Cell start, const std::vector<sdk::Cell>& path) {
  std::size_t turns = 0;
  sdk::Cell at = start;
  std::optional<sdk::Cell> heading;
  for (const sdk::Cell& next : path) {
    const sdk::Cell step{next.x - at.x, next.y - at.y, next.z - at.z};
    if (heading && step != *heading) ++turns;
    heading = step;
    at = next;
  }
  return turns;
}

std::vector<RunRow> measure_cell(const CellSpec& cell, const sdk::Geometry& g,
                                 const kernel::PluginRef<sdk::Planner>& planner,
                                 const std::vector<Task>& tasks) {
  std::vector<RunRow> rows;
  for (const Task& task : tasks) {
    RunRow row;
    row.world = cell.world;
    row.planner = cell.planner;
    row.plugin = cell.plugin;
    row.seed = cell.seed;
    row.task = task.name;
    row.start = sdk::to_string(task.start, g.dims());
    row.goal = sdk::to_string(task.goal, g.dims());
    row.shortest = task.shortest;
    const sdk::Area goal{task.goal};
    std::vector<double> cpu, wall;
    sdk::PathResult first;
    bool varies = false;
    std::string error;  // the code of an error the plan call threw (a plugin's exception)
    for (int rep = 0; rep < cell.repetitions && error.empty(); ++rep) {
      const bool probe = rep == 0 && reset_peak_rss();
      const auto rss_before = probe ? status_kib("VmRSS") : std::nullopt;
      const auto stop =
          sdk::StopCondition::within_cpu(std::chrono::milliseconds(cell.cpu_budget_ms),
                                         std::chrono::milliseconds(cell.deadline_ms));
      const auto wall0 = std::chrono::steady_clock::now();
      const double cpu0 = thread_cpu_us();
      sdk::PathResult r;
      try {
        // The kernel's own check (docs/plugins-untrusted.md): an invalid path is the error
        // invalid_plan here exactly as in `run`, `session`, `serve`, `dds` and `replay`.
        r = kernel::checked_plan(planner, g, sdk::PathRequest{task.start, &goal, nullptr}, stop);
      } catch (const sdk::Error& e) {
        error = e.code();
        std::cerr << "flipper: bench planners: " << cell.world << " x " << cell.planner << ", task "
                  << task.name << ": " << e.code() << ": " << e.what() << "\n";
      }
      cpu.push_back(thread_cpu_us() - cpu0);
      wall.push_back(
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - wall0)
              .count());
      if (probe) {
        row.peak_rss_kib = status_kib("VmHWM");
        if (row.peak_rss_kib && rss_before) row.memory_kib = *row.peak_rss_kib - *rss_before;
      }
      if (rep == 0 && r.status == sdk::PlanStatus::stopped) {
        const sdk::StopCause cause = stop.cause();
        if (cause != sdk::StopCause::none) row.stopped = sdk::to_string(cause);
      }
      if (rep == 0)
        first = std::move(r);
      else if (r.status != first.status || r.path != first.path)
        varies = true;
    }
    row.cpu_us = stats::median(cpu);
    row.wall_us = stats::median(wall);
    row.expansions = first.expansions;
    row.status = error.empty() ? sdk::to_string(first.status) : error;
    if (error.empty() && first.status == sdk::PlanStatus::found) {
      row.length = first.path.size();
      row.turns = count_turns(task.start, first.path);
    }
    if (varies) row.status = "varies";
    row.success = task.shortest ? row.status == "found" : row.status == "no_path";
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace flipper::planbench
