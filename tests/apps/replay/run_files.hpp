#pragma once
// Comparing two run folders file by file, leaving out what measures time (docs/experiments.md §3):
// figures.csv rows with timing 1, the `ms` column of queries.csv and `plan_cpu_ms` of
// accepts.csv, metrics.json's `latency_ours_ms` and `planner.plan_cpu_*`, plot panels marked
// timing and the pictures of figures that have one (latency, planner). manifest.json and
// report.md name dates, hosts and durations and are left out too. Everything else must be equal
// byte for byte (CSV, JSON, plot data) — PDF and SVG pictures included.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "flipper/record/csv.hpp"

namespace runfiles {

namespace fs = std::filesystem;

struct Comparison {
  std::vector<std::string> differing;  ///< files (relative) that differ or exist on one side
  std::size_t compared = 0;            ///< files compared (pictures included)
  std::size_t pictures = 0;            ///< PDF and SVG files compared byte for byte
  std::string text;                    ///< what differs, for a failure message
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A CSV without its timing columns (and, for figures.csv, its timing rows), as text.
inline std::string csv_without_timing(const fs::path& p) {
  const auto t = flipper::record::read_csv(p.string());
  const std::set<std::string> timing_columns = {"ms", "plan_cpu_ms"};
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (!timing_columns.count(t.header[i])) keep.push_back(i);
  const bool figures = p.filename() == "figures.csv";
  const std::size_t timing = figures ? t.column("timing", p.string()) : 0;
  std::string out;
  auto line = [&](const std::vector<std::string>& row) {
    std::vector<std::string> cells;
    for (std::size_t i : keep) cells.push_back(row[i]);
    out += flipper::record::csv_line(cells) + "\n";
  };
  line(t.header);
  for (const auto& row : t.rows)
    if (!figures || row[timing] == "0") line(row);
  return out;
}

inline nlohmann::json json_without_timing(const fs::path& p) {
  nlohmann::json j = nlohmann::json::parse(slurp(p));
  if (p.filename() == "metrics.json") {
    j.erase("latency_ours_ms");
    for (const char* k : {"plan_cpu_ms", "plan_cpu_ms_p50", "plan_cpu_ms_p90"})
      j["planner"].erase(k);
  } else if (j.contains("panels")) {
    nlohmann::json kept = nlohmann::json::array();
    for (const auto& panel : j["panels"])
      if (!panel.value("timing", false)) kept.push_back(panel);
    j["panels"] = kept;
  }
  return j;
}

// Whether a picture's figure has a timing panel (its plot data says so).
inline bool timing_picture(const fs::path& picture) {
  fs::path data = picture;
  data.replace_extension(".plotdata.json");
  if (!fs::exists(data)) return false;
  const nlohmann::json plot = nlohmann::json::parse(slurp(data));
  for (const auto& panel : plot.at("panels"))
    if (panel.value("timing", false)) return true;
  return false;
}

inline Comparison compare_runs(const fs::path& a, const fs::path& b) {
  Comparison c;
  std::set<std::string> seen;
  auto differ = [&](const std::string& rel, const std::string& why) {
    c.differing.push_back(rel);
    c.text += rel + ": " + why + "\n";
  };
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), a).string();
    seen.insert(rel);
    const std::string name = e.path().filename().string();
    if (name == "manifest.json" || name == "report.md") continue;
    const fs::path other = b / rel;
    if (!fs::exists(other)) {
      differ(rel, "only in " + a.string());
      continue;
    }
    const std::string ext = e.path().extension().string();
    if (ext == ".pdf" || ext == ".svg") {
      if (timing_picture(e.path())) continue;
      ++c.pictures;
      ++c.compared;
      if (slurp(e.path()) != slurp(other)) differ(rel, "picture bytes differ");
      continue;
    }
    ++c.compared;
    if (ext == ".csv") {
      if (csv_without_timing(e.path()) != csv_without_timing(other)) differ(rel, "rows differ");
    } else if (ext == ".json") {
      if (json_without_timing(e.path()) != json_without_timing(other)) differ(rel, "JSON differs");
    } else if (slurp(e.path()) != slurp(other)) {
      differ(rel, "bytes differ");
    }
  }
  for (const auto& e : fs::recursive_directory_iterator(b))
    if (e.is_regular_file() && !seen.count(fs::relative(e.path(), b).string()))
      differ(fs::relative(e.path(), b).string(), "only in " + b.string());
  return c;
}

}  // namespace runfiles
