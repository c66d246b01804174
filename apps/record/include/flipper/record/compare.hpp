#pragma once
/// @file compare.hpp
/// Two runs side by side (docs/experiments.md §6): per condition (a variant, or the variants that
/// differ only in their seeds) each figure of run A and of run B, as a value, or over seeds as
/// mean ± sd (min–max, n), and the difference of the means. Only figures that differ are listed
/// unless `all` is set; timing figures are listed apart.

#include <string>
#include <vector>

#include "flipper/record/figures.hpp"

namespace flipper::record {

struct RunFigures {
  std::string label;  ///< how the run is named in the text (its folder)
  std::vector<Figure> figures;
  std::vector<VariantInfo> variants;
};
/// Reads a run folder's figures.csv, variants.csv and settings.csv.
RunFigures read_run_figures(const std::string& run_dir);

/// How many figures (timing ones apart) were compared, and how many of them differ.
struct ComparisonCounts {
  std::size_t compared = 0, differing = 0;
};

/// The comparison as Markdown; figures in natural order (numbers inside names compare as numbers:
/// `rank_2` before `rank_10`). When nothing was compared (no condition in both runs) it says so
/// instead of "0 of 0 figures differ". `counts`, when given, receives the counts.
std::string compare_runs(const RunFigures& a, const RunFigures& b, bool all,
                         ComparisonCounts* counts = nullptr);

/// A figure's value as a report shows it: integers without decimals, others with up to 4
/// significant decimals ("97.0", "0.0125", "3830").
std::string show_value(double value);

}  // namespace flipper::record
