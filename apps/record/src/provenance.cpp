// What a run ran on, read when it runs (docs/experiments.md §2): the source tree's commit and
// state by git, the libraries the build was made against, the plugins' origins.
#include <sqlite3.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <vector>

#include "flipper/kernel/loader.hpp"
#include "flipper/record/build_info.hpp"
#include "flipper/record/manifest.hpp"

namespace flipper::record {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Standard output of a shell command, trailing newline removed; nullopt when it fails.
std::optional<std::string> command_output(const std::string& command) {
  FILE* p = ::popen((command + " 2>/dev/null").c_str(), "r");
  if (p == nullptr) return std::nullopt;
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  if (::pclose(p) != 0) return std::nullopt;
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

json source_json(const std::string& tree) {
  const BuildInfo& b = build_info();
  json out = {{"tree", tree},          {"commit", "unknown"}, {"describe", "unknown"},
              {"dirty", "unknown"},    {"read", "run time"},  {"build_commit", b.commit},
              {"build_dirty", b.dirty}};
  std::error_code ec;
  if (tree.empty() || !fs::is_directory(tree, ec)) {
    out["read"] = "no source tree (the build's own values only)";
    return out;
  }
  const std::string git = "git -C " + quote(tree) + " ";
  // Only the tree's own repository counts (as at build time: cmake/FlipperBuildInfo.cmake).
  const auto top = command_output(git + "rev-parse --show-toplevel");
  if (!top || fs::weakly_canonical(*top, ec) != fs::weakly_canonical(tree, ec)) {
    out["read"] = "not a git checkout (the build's own values only)";
    return out;
  }
  if (const auto commit = command_output(git + "rev-parse HEAD")) out["commit"] = *commit;
  if (const auto describe = command_output(git + "describe --always --dirty"))
    out["describe"] = *describe;
  // Tracked files changed (staged or not); untracked files do not change what was built.
  if (const auto status = command_output(git + "status --porcelain --untracked-files=no"))
    out["dirty"] = status->empty() ? "no" : "yes";
  return out;
}

// The source tree of the build tree this executable runs from (its CMakeCache.txt names it:
// build/bin/flipper beside build/CMakeCache.txt); "" for an installed executable. No path is
// compiled in.
std::string source_tree() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  std::ifstream cache(exe.parent_path().parent_path() / "CMakeCache.txt");
  const std::string key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
  for (std::string line; std::getline(cache, line);)
    if (line.rfind(key, 0) == 0) return line.substr(key.size());
  return "";
}

json source_json() {
  return source_json(source_tree());
}

json libraries_json() {
  return {{"compiler", FLIPPER_RECORD_COMPILER},
          {"ompl", FLIPPER_RECORD_OMPL_VERSION},
          {"fcl", FLIPPER_RECORD_FCL_VERSION},
          {"octomap", FLIPPER_RECORD_OCTOMAP_VERSION},
          {"eigen", FLIPPER_RECORD_EIGEN_VERSION},
          {"boost", FLIPPER_RECORD_BOOST_VERSION},
          {"cyclonedds", FLIPPER_RECORD_CYCLONEDDS_VERSION},
          {"sqlite", FLIPPER_RECORD_SQLITE_VERSION},
          {"sqlite_loaded", sqlite3_libversion()}};
}

json plugin_origin_json(const kernel::PluginLoader& loader, const std::string& library) {
  json shadows = json::array();
  std::string dir, name;
  for (const auto& e : loader.entries())
    if (e.library == library) {
      dir = e.dir;
      name = e.name;
    }
  for (const auto& e : loader.entries())
    if (e.name == name && e.shadowed_by == library) shadows.push_back(e.library);
  // The plugins built with flipper lie in the folder beside the executable (the loader's last
  // search directory); any other folder is out of tree (plugin_paths, FLIPPER_PLUGIN_PATH).
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path own =
      fs::weakly_canonical(exe.parent_path() / ".." / "lib" / "flipper" / "plugins", ec);
  const bool in_tree = !dir.empty() && fs::weakly_canonical(dir, ec) == own;
  return {{"dir", dir}, {"in_tree", in_tree}, {"shadows", shadows}};
}

std::vector<std::string> shadow_notes(const json& plugins) {
  std::vector<std::string> out;
  for (const auto& p : plugins) {
    const json origin = p.value("origin", json::object());
    for (const auto& hidden : origin.value("shadows", json::array()))
      out.push_back("plugin '" + p.value("name", std::string()) + "' (" +
                    p.value("file", std::string()) + ") shadows " + hidden.get<std::string>());
  }
  return out;
}

}  // namespace flipper::record
