#pragma once
/// @file output.hpp
/// Writing a replay's results: metrics.json, queries.csv, participants.csv, groups.csv,
/// accepts.csv, definitions.csv (metrics_io.cpp); SVG figures (svg.cpp); report.md (report.cpp).

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "flipper/replay/metrics.hpp"
#include "flipper/replay/records.hpp"

namespace flipper::kernel::replay {

/// The metrics report, written indented to metrics.json for people to read. The one use of
/// nlohmann::ordered_json in the tree: the report's sections stay in reading order (agreement
/// first) in an indented file, which the protocol's JsonWriter (compact only) does not write.
nlohmann::ordered_json metrics_json(const Metrics& m);
/// Writes metrics.json and the CSV files into `dir` (created).
void write_metrics(const std::string& dir, const ReplayResult& result, const Metrics& m);

/// A grouped bar chart: one cluster per category, one bar per series; optional whiskers.
struct BarChart {
  std::string title, y_label;
  std::vector<std::string> categories, series;
  std::vector<std::vector<double>> values;     ///< [series][category]
  std::vector<std::vector<double>> low, high;  ///< optional whiskers, same shape
};
std::string render_svg(const BarChart& chart);

/// Writes tokens.svg, induced_core.svg, others_self.svg, latency.svg into `dir`.
void write_figures(const std::string& dir, const Metrics& m);

struct Variant {
  std::string name;
  std::vector<std::string> sets;
  Metrics metrics;
  std::string dir;  ///< relative to the report's directory
};
/// Cross-variant comparison (variants.cpp): variants.svg in `dir` (status agreement by group,
/// tokens of successful commands, induced vs core commands; one bar per variant) and the report
/// section that shows it with its table (agreement, Nothing turned into readings, floating tops).
void write_variant_figure(const std::string& dir, const std::vector<Variant>& variants);
void write_variant_section(std::ostream& o, const std::vector<Variant>& variants);

/// report.md in `dir`: per variant the figures (ours | original | paper), agreement, confusion,
/// execution, latency, definitions; with several variants a side-by-side table first.
void write_report(const std::string& dir, const std::string& title,
                  const std::vector<Variant>& variants, const std::string& corpus,
                  const std::vector<std::string>& runs);

}  // namespace flipper::kernel::replay
