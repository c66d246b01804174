// A benchmark run's files from its runs.csv (docs/planners.md §5).
#include "assemble.hpp"

#include <stdlib.h>

#include <sstream>

#include "flipper/planbench/summary.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/durable_file.hpp"
#include "flipper/record/out_file.hpp"

namespace flipper::planbench::detail {
namespace {

// The tasks whose process died, first in the report: no figure of theirs is in the tables but
// their row (status plugin_crashed, crashed, wall_backstop or failed).
std::string failures_text(const nlohmann::json& failures) {
  if (failures.empty()) return "";
  std::string out =
      "## Failed tasks\n\n" + std::to_string(failures.size()) +
      " task(s) lost their process; the cell's other tasks ran in a new one "
      "(docs/planners.md §5). The rest of the run is complete.\n\n"
      "| world | planner | seed | task | status | cause |\n|---|---|---|---|---|---|\n";
  for (const auto& f : failures)
    out += "| " + f.value("world", "") + " | " + f.value("planner", "") + " | " +
           f.value("seed", "") + " | " + f.value("task", "") + " | " + f.value("status", "") +
           " | " + f.value("cause", "") + " |\n";
  return out + "\n";
}

void write_report(const std::string& run_dir, const ReportHead& e, const record::CsvTable& runs,
                  const nlohmann::json& failures) {
  record::OutFile out(run_dir + "/report.md");
  out << "# Planner benchmark: " << e.name << "\n\n"
      << "Experiment `" << e.file << "`; " << e.worlds << " worlds × " << e.planners
      << " planners, " << e.cells << " cells (world × planner × seed), " << runs.rows.size()
      << " plans. Files: `manifest.json` (build, plugins with SHA-256, each cell's config, "
         "inputs), `tasks.csv` (each world's tasks with the oracle's shortest length), "
         "`runs.csv` (one row per plan), `figures.csv`, `variants.csv`, the plots "
         "(`planners.pdf`, `.svg`).\n\n"
      << e.shard_note << failures_text(failures) << "## Results (deterministic)\n\n"
      << "Length in steps; length / shortest against a breadth-first oracle over the world's "
         "cells; means over the successful plans, success over all (tasks × seeds). \"Stopped "
         "for time\": plans a time limit ended, not planning failures: `cpu_budget` (the "
         "experiment's cpu_budget_ms of the planning thread's CPU time) or `wall_backstop` (its "
         "deadline_ms of wall time, a runaway guard).\n\n"
      << results_table(runs) << "\n## Over seeds: 95 % confidence intervals\n\n"
      << "Success over all plans (tasks × seeds) with its Wilson score interval; length / "
         "shortest and length: the mean over seeds of each seed's mean over its successful "
         "plans, with Student's t interval over the seeds (`[–]`: one seed, no interval). "
         "Method: docs/planners.md §5, \"Intervals\".\n\n"
      << intervals_table(runs) << "\n## Timing (measured)\n\n"
      << "Measured on " << e.measured_on
      << ": plan CPU time is the planning thread's CPU time, the median of " << e.repetitions
      << " repetition(s) per task; memory is the peak resident set during the plan "
         "(VmHWM, reset before it) and its growth over the resident set before it.\n\n"
      << timing_table(runs);
  out.close();
}

}  // namespace

std::string load_text() {
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 1) return "unknown";
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << load[0];
  return s.str();
}

std::string measured_on(const nlohmann::json& host, const std::string& load) {
  return host.value("name", std::string("?")) + " (" + std::to_string(host.value("cores", 0)) +
         " cores, load " + load + " at the start)";
}

std::string run_status(std::size_t failures, std::size_t rows) {
  return failures == 0 ? "complete" : failures >= rows ? "failed" : "partial";
}

BenchResult assemble_bench(const std::string& run_dir, const ReportHead& head,
                           const nlohmann::json& failures, bool plots) {
  BenchResult result;
  result.run_dir = run_dir;
  result.cells = head.cells;
  const record::CsvTable runs = record::read_csv(run_dir + "/runs.csv");
  result.runs = runs.rows.size();
  result.failures = failures.size();
  const BenchFigures figures = bench_figures(runs);
  record::write_figures(run_dir + "/figures.csv", figures.figures);
  record::write_variants(run_dir, figures.variants);
  record::write_file_atomically(run_dir + "/intervals.csv", intervals_csv(figures));
  write_report(run_dir, head, runs, failures);
  result.status = run_status(failures.size(), runs.rows.size());
  if (plots) result.plots = record::draw_plots("planner_bench_plots.py", run_dir);
  return result;
}

}  // namespace flipper::planbench::detail
