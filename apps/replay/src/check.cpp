// Re-checking a run from its manifest; merging shard runs (check.hpp).
#include "flipper/replay/check.hpp"

#include <unistd.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "flipper/record/compare.hpp"
#include "flipper/record/csv.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::replay {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json complete_replay_manifest(const std::string& run_dir) {
  json m = record::read_manifest(run_dir);
  if (m.value("kind", std::string()) != "replay")
    throw sdk::Error(sdk::codes::kBadRequest, "'" + run_dir + "' is not a replay run");
  if (m.value("status", std::string()) != "complete")
    throw sdk::Error(sdk::codes::kBadRequest, "'" + run_dir + "' did not complete (status '" +
                                                  m.value("status", std::string("unknown")) + "')");
  return m;
}

std::optional<record::Shard> shard_of(const json& m) {
  if (!m.contains("shard") || !m["shard"].is_object()) return std::nullopt;
  return record::Shard{m["shard"].value("index", 0), m["shard"].value("count", 1)};
}

// What makes two shards parts of one experiment: the experiment without its file, config and
// corpus paths (shards may run from different checkouts; the corpus is compared by checksum and
// each variant's effective config by provenance_warnings).
json identity(json experiment) {
  for (const char* key : {"file", "config", "corpus"}) experiment.erase(key);
  return experiment;
}

// A temporary parent folder for a re-run that is not kept.
std::string temporary_parent() {
  std::string pattern = (fs::temp_directory_path() / "flipper-check-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw sdk::Error(sdk::codes::kWriteFailed, "cannot create a temporary folder for the re-run");
  return pattern;
}

// A difference: deterministic figures exactly (the text figures.csv holds), timings as shown.
std::string change_line(const record::FigureDiff::Change& c, bool timing) {
  const auto text = timing ? record::show_value : record::exact_number;
  return "  " + record::describe(c.key) + ": recorded " + text(c.a) + ", now " + text(c.b) +
         (c.unit.empty() ? "" : " " + c.unit);
}

}  // namespace

CheckResult check_run(const std::string& run_dir, int jobs, const std::string& keep_under) {
  const json recorded = complete_replay_manifest(run_dir);
  const Experiment e = experiment_from_json(recorded.at("experiment"));
  const std::string parent = keep_under.empty() ? temporary_parent() : keep_under;
  CheckResult result;
  RunOptions options;
  options.out = parent;
  options.jobs = jobs;
  options.shard = shard_of(recorded);
  options.plots = !keep_under.empty();
  RunSummary fresh;
  try {
    fresh = run_experiment(e, options);
  } catch (...) {
    if (keep_under.empty()) fs::remove_all(parent);
    throw;
  }
  result.warnings = record::provenance_warnings(recorded, record::read_manifest(fresh.run_dir));
  result.diff = record::diff_figures(record::read_figures(run_dir + "/figures.csv"), fresh.figures);
  if (keep_under.empty()) {
    std::error_code ec;
    fs::remove_all(parent, ec);
  } else {
    result.rerun_dir = fresh.run_dir;
  }

  std::ostringstream o;
  const auto& d = result.diff;
  o << "check " << run_dir << ": re-ran " << fresh.variants.size()
    << " variant(s) from the manifest"
    << (keep_under.empty() ? " (in a temporary folder, removed)" : " into " + fresh.run_dir)
    << "\n";
  for (const auto& w : result.warnings) o << "warning: " << w << "\n";
  if (!result.warnings.empty())
    o << "(the figures are compared all the same; a difference below may come from the above)\n";
  if (d.changed.empty())
    o << "figures: " << d.compared << " compared, none differs\n";
  else
    o << "figures: " << d.changed.size() << " of " << d.compared << " differ:\n";
  for (const auto& c : d.changed) o << change_line(c, false) << "\n";
  for (const auto& k : d.only_a) o << "  " << record::describe(k) << ": missing in the re-run\n";
  for (const auto& k : d.only_b) o << "  " << record::describe(k) << ": not in the recorded run\n";
  if (!d.timing.empty()) {
    o << "timing figures (measured time: never counted as differences): " << d.timing.size()
      << " differ, e.g.\n";
    for (std::size_t i = 0; i < d.timing.size() && i < 3; ++i)
      o << change_line(d.timing[i], true) << "\n";
  }
  o << (result.differs() ? "result: the run does NOT reproduce\n" : "result: the run reproduces\n");
  result.text = o.str();
  return result;
}

RunSummary merge_runs(const std::vector<std::string>& runs, const std::string& out, bool plots,
                      std::vector<std::string>& warnings) {
  if (runs.empty()) throw sdk::Error(sdk::codes::kBadRequest, "no runs to merge");
  std::vector<json> manifests;
  manifests.reserve(runs.size());
  for (const auto& r : runs) manifests.push_back(complete_replay_manifest(r));
  const json& first = manifests.front();
  std::map<int, std::string> by_index;
  int count = -1;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const json& m = manifests[i];
    const auto shard = shard_of(m);
    if (!shard)
      throw sdk::Error(sdk::codes::kBadRequest,
                       "'" + runs[i] + "' is not a shard (it ran without --shard I/N)");
    if (identity(m.at("experiment")) != identity(first.at("experiment")))
      throw sdk::Error(sdk::codes::kBadRequest,
                       "'" + runs[i] + "' and '" + runs[0] +
                           "' are shards of different experiments (their manifests' "
                           "'experiment' differ)");
    if (m.at("corpus").at("files") != first.at("corpus").at("files"))
      throw sdk::Error(sdk::codes::kBadRequest, "'" + runs[i] + "' and '" + runs[0] +
                                                    "' read different corpus files (checksums)");
    if (count >= 0 && shard->count != count)
      throw sdk::Error(sdk::codes::kBadRequest, "'" + runs[i] + "' is a shard of " +
                                                    std::to_string(shard->count) + ", '" + runs[0] +
                                                    "' of " + std::to_string(count));
    count = shard->count;
    auto [it, fresh] = by_index.emplace(shard->index, runs[i]);
    if (!fresh)
      throw sdk::Error(sdk::codes::kBadRequest, "shard " + std::to_string(shard->index) +
                                                    " is given twice: '" + it->second + "' and '" +
                                                    runs[i] + "'");
    if (i > 0)
      for (const auto& w : record::provenance_warnings(first, m))
        warnings.push_back(runs[i] + " vs " + runs[0] + ": " + w);
  }
  std::string missing;
  for (int k = 0; k < count; ++k)
    if (!by_index.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (!missing.empty())
    throw sdk::Error(sdk::codes::kBadRequest,
                     "shard(s) " + missing + " of " + std::to_string(count) + " missing");

  // Every variant of the grid exactly once, in the grid's order.
  const Experiment e = experiment_from_json(first.at("experiment"));
  std::map<std::string, std::pair<json, std::string>> found;  // name -> (entry, run)
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (const auto& v : manifests[i].value("variants", json::array())) {
      const std::string name = v.at("name").get<std::string>();
      auto [it, fresh] = found.emplace(name, std::make_pair(v, runs[i]));
      if (!fresh)
        throw sdk::Error(sdk::codes::kBadRequest, "variant '" + name + "' was run twice: in '" +
                                                      it->second.second + "' and '" + runs[i] +
                                                      "'");
    }
  json variants = json::array();
  std::vector<std::string> from;
  std::string absent;
  for (const auto& p : plan_variants(e)) {
    auto it = found.find(p.info.name);
    if (it == found.end()) {
      absent += (absent.empty() ? "'" : ", '") + p.info.name + "'";
      continue;
    }
    variants.push_back(it->second.first);
    from.push_back(it->second.second);
    found.erase(it);
  }
  if (!absent.empty())
    throw sdk::Error(sdk::codes::kBadRequest, "the shards lack variant(s) " + absent);
  if (!found.empty())
    throw sdk::Error(sdk::codes::kBadRequest, "variant '" + found.begin()->first + "' (in '" +
                                                  found.begin()->second.second +
                                                  "') is not in the experiment's grid");

  json manifest = first;
  const std::string stem =
      (e.file.empty() ? std::string("replay") : fs::path(e.file).stem().string()) + "-merged";
  const std::string run_dir = record::create_run_folder(out, stem);
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const std::string dir = variants[i].at("directory").get<std::string>();
    fs::copy(fs::path(from[i]) / dir, fs::path(run_dir) / dir, fs::copy_options::recursive);
  }
  json merged = json::array();
  std::string started = first.value("started", std::string()), finished;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const json& m = manifests[i];
    merged.push_back({{"run", fs::absolute(runs[i]).lexically_normal().string()},
                      {"shard", m["shard"]},
                      {"build", m["build"]},
                      {"host", m["host"]},
                      {"command", m["command"]},
                      {"started", m["started"]},
                      {"finished", m["finished"]}});
    started = std::min(started, m.value("started", started));
    finished = std::max(finished, m.value("finished", finished));
  }
  manifest["run"] = fs::path(run_dir).filename().string();
  manifest["shard"] = json();
  manifest["merged_from"] = merged;
  manifest["variants"] = variants;
  manifest["started"] = started;
  manifest["finished"] = finished;
  manifest["command"] = record::command_json();
  manifest["status"] = "running";
  manifest.erase("plots");
  record::write_manifest(run_dir, manifest);
  return assemble_run(run_dir, manifest, plots);
}

}  // namespace flipper::replay
