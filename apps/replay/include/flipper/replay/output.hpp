#pragma once
/// @file output.hpp
/// Writing a replay's results. Per variant (metrics_io.cpp): metrics.json, queries.csv,
/// participants.csv, groups.csv, accepts.csv, definitions.csv, deletions.csv. Per run
/// (report.cpp, tables.cpp): report.md and the Markdown tables it shares with `flipper replay
/// --print`, all read from the run's figures (figures.hpp) and manifest, never from memory, so
/// a report shows only figures that figures.csv has.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "flipper/record/figures.hpp"
#include "flipper/replay/metrics.hpp"
#include "flipper/replay/records.hpp"

namespace flipper::replay {

/// The metrics report, written indented to metrics.json for people to read. The one use of
/// nlohmann::ordered_json in the tree: the report's sections stay in reading order (agreement
/// first) in an indented file, which the protocol's toolkit::json::JsonWriter (compact only) does
/// not write.
nlohmann::ordered_json metrics_json(const Metrics& m);
/// Writes metrics.json and the CSV files into `dir` (created).
void write_metrics(const std::string& dir, const ReplayResult& result, const Metrics& m);

/// A mean as the report shows it: one decimal ("97.0", "1435.0").
std::string one_decimal(double v);
/// A duration in ms as the report shows it: µs below 1 ms ("21 µs", "4.2 µs"), else ms.
std::string duration_text(double ms);

/// The variants side by side (Markdown): status agreement all / A / B / C, the original's Core
/// queries we parse as core, the original's Nothing queries we give a reading, floating tops,
/// accepts whose program is our first / among our first three / matched, tokens of successful
/// commands per participant, induced and core commands per participant.
std::string variants_table(const record::FigureTable& figures,
                           const std::vector<record::VariantInfo>& variants);
/// The headline per variant (Markdown lines): status agreement, accepted programs found,
/// executions agreeing with the logged next world.
std::string headline_text(const record::FigureTable& figures,
                          const std::vector<record::VariantInfo>& variants);
/// The oracles per variant (Markdown lines): induced rules against the original's logged ones,
/// execution differences nothing explains.
std::string oracles_text(const record::FigureTable& figures,
                         const std::vector<record::VariantInfo>& variants);
/// The rule-identity oracle per variant (Markdown lines): definitions whose induced rules equal
/// the original's (identical or already present) and the differing ones by class
/// (rule_oracle.hpp classify_rules).
std::string rules_text(const record::FigureTable& figures,
                       const std::vector<record::VariantInfo>& variants);
/// The planner on the accepted programs per variant (Markdown table): runs, success, path
/// length and turns (mean per executed program), planner calls, plan CPU time (timing).
std::string planner_table(const record::FigureTable& figures,
                          const std::vector<record::VariantInfo>& variants);
/// Conditions over their seeds (Markdown table: mean ± sd, min–max), "" when no variant has a
/// seed setting.
std::string seeds_table(const std::vector<record::Figure>& figures,
                        const std::vector<record::VariantInfo>& variants);

/// report.md in `run_dir`: what the run is (manifest: version, commit, plugins, files and
/// checksums, effective configs, corpus, seeds, command, host, dates), the variants side by
/// side, then each variant's figures (ours | original | paper), agreement, confusion,
/// execution, planner, latency, definitions.
void write_report(const std::string& run_dir, const nlohmann::json& manifest,
                  const std::vector<record::VariantInfo>& variants,
                  const std::vector<record::Figure>& figures);

}  // namespace flipper::replay
