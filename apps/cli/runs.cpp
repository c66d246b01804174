// flipper runs list PARENT
// flipper runs show RUN
// An index of run folders from their manifests (docs/experiments.md §1): every run under a
// parent with its kind, status, dates, experiment, lost work and source commit; one run's
// provenance and lost work in a few lines.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/record/run_folder.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::cli {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string text(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>()
                                                                : std::string("–");
}

// "5901c49 (dirty)" from the source read at run time, else the build's.
std::string commit_text(const json& m) {
  const json s = m.value("source", m.value("build", json::object()));
  const std::string commit = text(s, "commit");
  const std::string dirty = text(s, "dirty");
  return commit.substr(0, 7) + (dirty == "yes" ? " (dirty)" : "");
}

int list_runs(const std::string& parent) {
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw sdk::Error(sdk::codes::kBadRequest, "'" + parent + "' is not a folder");
  if (record::is_run_folder(parent))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "'" + parent + "' is a run folder: `flipper runs show " + parent + "`");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(parent, ec))
    if (!e.is_symlink() && e.is_directory() && record::is_run_folder(e.path().string()))
      names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());  // <stem>-<UTC time>: by experiment, then time
  const fs::path latest = fs::read_symlink(fs::path(parent) / "latest", ec);
  std::cout << "| run | kind | status | started | finished | experiment | lost | commit |\n"
            << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& name : names) {
    json m;
    try {
      m = record::read_manifest((fs::path(parent) / name).string());
    } catch (const sdk::Error& e) {
      std::cout << "| " << name << " | – | unreadable manifest | – | – | – | – | – |\n";
      continue;
    }
    const json failed = m.value("failed", json::array());
    std::cout << "| " << name << (!latest.empty() && latest.string() == name ? " (latest)" : "")
              << " | " << text(m, "kind") << " | " << text(m, "status") << " | "
              << text(m, "started") << " | " << text(m, "finished") << " | "
              << text(m.value("experiment", json::object()), "name") << " | "
              << (failed.is_array() ? failed.size() : 0) << " | " << commit_text(m) << " |\n";
  }
  std::cout << names.size() << " run(s) in " << parent << "\n";
  return kExitOk;
}

int show_run(const std::string& run) {
  const json m = record::read_manifest(run);
  const json b = m.value("build", json::object()), s = m.value("source", json::object());
  const json e = m.value("experiment", json::object());
  std::cout << "run: " << fs::absolute(run).lexically_normal().string() << "\n"
            << "kind: " << text(m, "kind") << "\nstatus: " << text(m, "status") << "\n"
            << "experiment: " << text(e, "name") << " (" << text(e, "file") << ")\n"
            << "started: " << text(m, "started") << "\nfinished: " << text(m, "finished") << "\n"
            << "flipper: " << text(b, "flipper") << " built from " << text(b, "commit")
            << " (dirty: " << text(b, "dirty") << ")\n";
  if (s.is_object() && !s.empty())
    std::cout << "source tree: " << text(s, "tree") << " at " << text(s, "commit")
              << " (dirty: " << text(s, "dirty") << "; " << text(s, "read") << ")\n";
  const json libs = b.value("libraries", json::object());
  if (!libs.empty()) {
    std::cout << "libraries:";
    for (auto it = libs.begin(); it != libs.end(); ++it)
      std::cout << " " << it.key() << " "
                << (it.value().is_string() ? it.value().get<std::string>() : "?");
    std::cout << "\n";
  }
  const json host = m.value("host", json::object());
  std::cout << "host: " << text(host, "name") << ", jobs " << m.value("jobs", 0) << "\n";
  const json failed = m.value("failed", json::array());
  std::cout << "lost: " << (failed.is_array() ? failed.size() : 0) << "\n";
  for (const auto& f : failed)
    std::cout << "  "
              << (f.contains("variant") ? text(f, "variant")
                                        : text(f, "planner") + " on " + text(f, "world") +
                                              ", task " + text(f, "task"))
              << ": " << text(f, "cause") << "\n";
  std::cout << "report: " << (fs::path(run) / "report.md").string() << "\n";
  return kExitOk;
}

}  // namespace

void add_runs_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("runs", "An index of run folders from their manifests");
  cmd->require_subcommand(1);
  static CommonOptions opts;
  add_common_options(*cmd, opts);
  auto* list = cmd->add_subcommand("list", "Every run under a parent folder (--out of the runs)");
  static std::string parent;
  list->add_option("parent", parent, "The parent folder")->required();
  on_run(*list, [] { return reporting_errors("runs list", [] { return list_runs(parent); }); });
  auto* show = cmd->add_subcommand("show", "One run: status, provenance, lost work");
  static std::string run;
  show->add_option("run", run, "The run folder")->required();
  on_run(*show, [] { return reporting_errors("runs show", [] { return show_run(run); }); });
}

}  // namespace flipper::cli
