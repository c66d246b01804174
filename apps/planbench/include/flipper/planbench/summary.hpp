#pragma once
/// @file summary.hpp
/// What a benchmark run's runs.csv says (docs/planners.md §5): per world × planner, over its
/// tasks and seeds. `results_table` has the deterministic columns only (the README's table),
/// `timing_table` the measured ones; `bench_figures` the per-cell figures of figures.csv.

#include <string>
#include <vector>

#include "flipper/record/csv.hpp"
#include "flipper/record/figures.hpp"

namespace flipper::planbench {

/// success, length / shortest (mean, worst), turns, expansions, and the runs a time limit
/// stopped (`cpu_budget`, `wall_backstop`: not planning failures), per world × planner.
std::string results_table(const record::CsvTable& runs);
/// Per world × planner over its seeds (docs/planners.md §5, "Intervals"): the success rate
/// over all its plans with its 95 % Wilson score interval, and the mean over seeds of each
/// seed's mean length / shortest and length (its successful plans) with its 95 % Student's t
/// interval ("[–]" with one seed). Deterministic columns only.
std::string intervals_table(const record::CsvTable& runs);
/// plan CPU time (median, spread of the seeds' medians and their 95 % t
/// interval), wall time, peak memory.
std::string timing_table(const record::CsvTable& runs);

/// One variant per cell (`world=W,planner=P[,seed=S]`, its condition without the seed) and
/// its figures: tasks, solved, success (%), length_ratio_mean, length_ratio_max, turns_mean,
/// expansions_median; measured: cpu_us_median, cpu_us_max, peak_rss_kib_max.
struct BenchFigures {
  std::vector<record::Figure> figures;
  std::vector<record::VariantInfo> variants;
};
BenchFigures bench_figures(const record::CsvTable& runs);

/// The error bars of the plots (intervals.csv, docs/planners.md §5 "Intervals"): per condition
/// (world × planner) and plotted figure, `condition,metric,seeds,mean,low,high,method,timing`.
/// `success`: the Wilson interval of all its plans (method `wilson`, in %); `length_ratio_mean`,
/// `turns_mean`, `cpu_us_median`: the mean of the seeds' figures (figures.csv) and its t interval
/// (method `t`; low and high empty with one seed; the low end cut at 1 for the ratio, 0 else).
std::string intervals_csv(const BenchFigures& figures);

}  // namespace flipper::planbench
