// The provenance parts of manifest.json, and comparing two manifests (docs/experiments.md §2).
#include "flipper/record/manifest.hpp"

#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "flipper/kernel/loader.hpp"
#include "flipper/record/build_info.hpp"
#include "flipper/record/checksum.hpp"
#include "flipper/record/durable_file.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace fs = std::filesystem;
using nlohmann::json;

json build_json() {
  const BuildInfo& b = build_info();
  return {{"flipper", b.version},   {"sdk", b.sdk},     {"commit", b.commit},
          {"describe", b.describe}, {"dirty", b.dirty}, {"libraries", libraries_json()}};
}

json command_json() {
  json argv = json::array();
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  for (std::string arg; std::getline(in, arg, '\0');) argv.push_back(arg);
  std::error_code ec;
  return {{"argv", argv}, {"cwd", fs::current_path(ec).string()}};
}

json host_json() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  utsname u{};
  ::uname(&u);
  return {{"name", name},
          {"system", u.sysname},
          {"release", u.release},
          {"machine", u.machine},
          {"cores", std::thread::hardware_concurrency()}};
}

json file_json(const std::string& role, const std::string& path) {
  std::error_code ec;
  const fs::path abs = fs::weakly_canonical(fs::absolute(path), ec);
  const std::string p = ec ? fs::absolute(path).string() : abs.string();
  return {{"role", role}, {"path", p}, {"bytes", fs::file_size(p, ec)}, {"sha256", sha256_file(p)}};
}

json folder_json(const std::string& dir) {
  std::error_code ec;
  const fs::path abs = fs::weakly_canonical(fs::absolute(dir), ec);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(abs, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  if (ec)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "cannot list '" + abs.string() + "': " + ec.message());
  std::sort(files.begin(), files.end());
  json list = json::array();
  for (const auto& f : files)
    list.push_back({{"name", f.filename().string()},
                    {"bytes", fs::file_size(f, ec)},
                    {"sha256", sha256_file(f.string())}});
  return {{"path", abs.string()}, {"files", list}};
}

json config_json(const kernel::Config& config) {
  json files = json::array();
  if (config.source() != "<embedded default>" && fs::is_regular_file(config.source()))
    files.push_back(file_json("config", config.source()));
  for (const auto* key : {&kernel::keys::kWorldFile, &kernel::keys::kGrammarFile}) {
    const std::string path = config.has(*key) ? config.get(*key) : std::string();
    if (!path.empty() && fs::is_regular_file(path))
      files.push_back(file_json(std::string(key->name), path));
  }
  json out{{"source", config.source()},
           {"base_dir", config.base_dir()},
           {"effective", config.dump()},
           {"files", files}};
  if (json lexicon = lexicon_json(config); !lexicon.is_null()) out["lexicon"] = std::move(lexicon);
  return out;
}

json plugins_json(const kernel::Config& config, const std::vector<std::string>& sections) {
  const kernel::PluginLoader loader(kernel::PluginLoader::search_path_for(config));
  json out = json::array();
  for (const auto& section : kernel::Config::plugin_sections()) {
    if (!config.has_section(section)) continue;
    if (!sections.empty() && std::find(sections.begin(), sections.end(), section) == sections.end())
      continue;
    sdk::PluginKind kind{};
    sdk::parse_kind(section.c_str(), kind);
    const kernel::LoadedPlugin plugin = loader.open(config.plugin_name(section), kind);
    json params = json::object();
    const sdk::Params effective = config.plugin_params(section, plugin.schema());
    for (const auto& [name, value] : effective.values()) params[name] = sdk::to_string(value);
    out.push_back({{"section", section},
                   {"name", plugin.entry.name},
                   {"version", plugin.descriptor->version},
                   {"file", plugin.entry.library},
                   {"sha256", sha256_file(plugin.entry.library)},
                   {"params", params},
                   {"origin", plugin_origin_json(loader, plugin.entry.library)}});
  }
  return out;
}

void write_manifest(const std::string& run_dir, const json& manifest) {
  const std::string path = run_dir + "/manifest.json";
  write_file_atomically(path, manifest.dump(2) + "\n");
}

json read_manifest(const std::string& run_dir) {
  const std::string path = run_dir + "/manifest.json";
  std::ifstream in(path);
  if (!in)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "'" + run_dir + "' is not a run folder (no manifest.json)");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw sdk::Error(sdk::codes::kBadRequest, "'" + path + "' is not valid JSON: " + e.what());
  }
}

namespace {

std::string text_at(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>()
                                                                : std::string("(none)");
}

// The first line where two texts differ, for a readable message.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ma = static_cast<bool>(std::getline(ia, la)),
               mb = static_cast<bool>(std::getline(ib, lb));
    if (!ma && !mb) return "";
    if (!ma || !mb || la != lb)
      return "line " + std::to_string(line) + ": '" + (ma ? la : "(end)") + "' was '" +
             (mb ? lb : "(end)") + "'";
  }
}

// Checksums by a stable label (what the file is and its name, not the folder it lies in on this
// machine, so a check on another machine compares the same files).
std::map<std::string, std::string> checksums(const json& manifest) {
  std::map<std::string, std::string> out;
  auto add_files = [&](const json& files, const std::string& prefix) {
    if (!files.is_array()) return;
    for (const auto& f : files)
      out[prefix + text_at(f, "role") + " " + fs::path(text_at(f, "path")).filename().string()] =
          text_at(f, "sha256");
  };
  add_files(manifest.value("inputs", json::array()), "input ");
  if (manifest.contains("corpus") && manifest["corpus"].contains("files"))
    for (const auto& f : manifest["corpus"]["files"])
      out["corpus file " + text_at(f, "name")] = text_at(f, "sha256");
  for (const auto& v : manifest.value("variants", json::array()))
    if (v.contains("config")) add_files(v["config"].value("files", json::array()), "");
  return out;
}

}  // namespace

std::vector<std::string> provenance_warnings(const json& recorded, const json& now) {
  std::vector<std::string> out;
  const json rb = recorded.value("build", json::object()), nb = now.value("build", json::object());
  for (const char* key : {"flipper", "sdk", "commit", "dirty"})
    if (text_at(rb, key) != text_at(nb, key))
      out.push_back(std::string("flipper ") + key + " differs: recorded " + text_at(rb, key) +
                    ", now " + text_at(nb, key));
  const json rsrc = recorded.value("source", json::object()),
             nsrc = now.value("source", json::object());
  for (const char* key : {"commit", "dirty"})
    if (rsrc.contains(key) && text_at(rsrc, key) != text_at(nsrc, key))
      out.push_back(std::string("source tree ") + key + " differs: recorded " + text_at(rsrc, key) +
                    ", now " + text_at(nsrc, key));
  const json now_list = now.value("variants", json::array());
  std::map<std::string, const json*> now_variants;
  for (const auto& v : now_list) now_variants[text_at(v, "name")] = &v;
  std::set<std::string> seen_plugins;
  for (const auto& v : recorded.value("variants", json::array())) {
    const std::string name = text_at(v, "name");
    auto it = now_variants.find(name);
    if (it == now_variants.end()) continue;
    const json& w = *it->second;
    const std::string rc = text_at(v.value("config", json::object()), "effective"),
                      nc = text_at(w.value("config", json::object()), "effective");
    if (rc != nc)
      out.push_back("variant '" + name + "': the effective config differs (" +
                    first_difference(nc, rc) + ")");
    const json plugin_list = w.value("plugins", json::array());
    std::map<std::string, const json*> now_plugins;
    for (const auto& p : plugin_list) now_plugins[text_at(p, "section")] = &p;
    for (const auto& p : v.value("plugins", json::array())) {
      const std::string section = text_at(p, "section");
      auto np = now_plugins.find(section);
      if (np == now_plugins.end()) continue;
      for (const char* key : {"name", "version", "sha256"}) {
        const std::string a = text_at(p, key), b = text_at(*np->second, key);
        const std::string line = "plugin " + section + " '" + text_at(p, "name") + "' " + key +
                                 " differs: recorded " + a + ", now " + b + " (" +
                                 text_at(*np->second, "file") + ")";
        if (a != b && seen_plugins.insert(line).second) out.push_back(line);
      }
    }
  }
  const auto rs = checksums(recorded), ns = checksums(now);
  for (const auto& [label, sum] : rs) {
    auto it = ns.find(label);
    if (it == ns.end())
      out.push_back(label + ": not read by the re-run");
    else if (it->second != sum)
      out.push_back(label + ": checksum differs (recorded " + sum.substr(0, 12) + "…, now " +
                    it->second.substr(0, 12) + "…)");
  }
  return out;
}

}  // namespace flipper::record
