#include "flipper/kernel/loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>

#include "flipper/sdk/host_loader.hpp"

namespace flipper::kernel {

namespace fs = std::filesystem;
using sdk::Error;
namespace codes = sdk::codes;

namespace {

constexpr const char* kSidecarSuffix = ".flipper.yaml";

PluginEntry read_sidecar(const fs::path& file, const std::string& dir) {
  PluginEntry e;
  e.sidecar = file.string();
  e.dir = dir;
  e.name = file.filename().string();
  e.name.resize(e.name.size() - std::strlen(kSidecarSuffix));
  try {
    const YAML::Node y = YAML::LoadFile(file.string());
    if (y["name"]) e.name = y["name"].as<std::string>();
    if (y["kind"]) e.kind = y["kind"].as<std::string>();
    if (y["version"]) e.version = y["version"].as<std::string>();
    if (y["dims"]) e.dims = y["dims"].as<int>();
    if (e.dims != 0 && e.dims != 2 && e.dims != 3)
      e.index_error = "sidecar '" + e.sidecar + "' says dims " + std::to_string(e.dims) +
                      " (world plugins read 2- or 3-D worlds)";
    const std::string lib = y["library"] ? y["library"].as<std::string>() : e.name + ".so";
    e.library = (file.parent_path() / lib).lexically_normal().string();
    std::error_code ec;
    if (!fs::exists(e.library, ec))
      e.index_error = "sidecar '" + e.sidecar + "' names library '" + e.library +
                      "', which does not exist (not built yet?)";
  } catch (const YAML::Exception& ex) {
    e.index_error = "cannot read sidecar '" + e.sidecar + "': " + ex.what();
  }
  return e;
}

// Sidecars first (they name their libraries), then the .so files no sidecar claims.
std::vector<PluginEntry> index_dir(const std::string& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& de : fs::directory_iterator(dir, ec))
    if (de.is_regular_file(ec)) files.push_back(de.path());
  std::sort(files.begin(), files.end());
  std::vector<PluginEntry> out;
  for (const auto& f : files)
    if (f.filename().string().ends_with(kSidecarSuffix)) out.push_back(read_sidecar(f, dir));
  for (const auto& f : files) {
    if (f.extension() != ".so") continue;
    const std::string lib = f.lexically_normal().string();
    if (std::any_of(out.begin(), out.end(), [&](const PluginEntry& e) { return e.library == lib; }))
      continue;
    PluginEntry e;
    e.name = f.stem().string();
    e.library = lib;
    e.dir = dir;
    out.push_back(std::move(e));
  }
  return out;
}

std::string kind_word(std::uint32_t kind) {
  return sdk::kind_name(static_cast<sdk::PluginKind>(kind));
}

}  // namespace

std::string LoadedPlugin::label() const {
  return "'" + entry.name + "' (" + entry.library + ")";
}

PluginId LoadedPlugin::id() const {
  return PluginId{
      entry.kind.empty() && descriptor != nullptr ? kind_word(descriptor->kind) : entry.kind,
      entry.name, entry.library};
}

// describe and create wrap every exception, sdk::Error included: a plugin that cannot even be
// built is the plugin's failure, whatever code it chose (docs/plugins.md).
sdk::ParamSchema LoadedPlugin::schema() const {
  sdk::ParamSchema schema;
  try {
    descriptor->describe(schema);
  } catch (const std::exception& e) {
    throw_plugin_failure(id(), "describe", e.what());
  } catch (...) {
    throw_plugin_failure(id(), "describe", "unknown exception");
  }
  return schema;
}

PluginLoader::PluginLoader(const std::vector<std::string>& search_path) {
  std::map<std::string, std::string> first_by_name;  // name -> library of the winning entry
  for (const auto& raw : search_path) {
    std::error_code ec;
    if (raw.empty() || !fs::is_directory(raw, ec)) continue;
    const std::string dir = fs::weakly_canonical(raw, ec).string();
    if (std::find(search_path_.begin(), search_path_.end(), dir) != search_path_.end()) continue;
    search_path_.push_back(dir);
    std::vector<PluginEntry> here = index_dir(dir);
    for (std::size_t i = 0; i < here.size(); ++i) {
      for (std::size_t j = 0; j < here.size(); ++j)
        if (i != j && here[i].name == here[j].name && here[i].duplicate_of.empty())
          here[i].duplicate_of = here[j].library;
      auto it = first_by_name.find(here[i].name);
      if (it != first_by_name.end() && fs::path(it->second).parent_path() != fs::path(dir))
        here[i].shadowed_by = it->second;
    }
    for (auto& e : here) {
      first_by_name.emplace(e.name, e.library);
      entries_.push_back(std::move(e));
    }
  }
}

std::vector<std::string> PluginLoader::search_path_for(const Config& config) {
  std::vector<std::string> path;
  // A plugin_paths entry that is not a directory is a config error, not silently skipped.
  const auto given = config.text(keys::kPluginPaths);
  const auto resolved = config.get(keys::kPluginPaths);
  for (std::size_t i = 0; i < resolved.size(); ++i) {
    std::error_code ec;
    if (!fs::is_directory(resolved[i], ec))
      throw sdk::Error(sdk::codes::kBadConfig, "plugin_paths entry '" + given[i] +
                                                   "' resolves to '" + resolved[i] +
                                                   "', which is not a directory (" +
                                                   config.path_origin(keys::kPluginPaths) + ")");
    path.push_back(resolved[i]);
  }
  if (const char* env = std::getenv("FLIPPER_PLUGIN_PATH")) {
    std::string s(env);
    for (std::size_t start = 0, colon;; start = colon + 1) {
      colon = s.find(':', start);
      std::string part = s.substr(start, colon - start);
      if (!part.empty()) path.push_back(part);
      if (colon == std::string::npos) break;
    }
  }
  // Found relative to the executable only, so no build or source path is compiled in: the
  // install layout, which the build tree mirrors (build/lib/flipper/plugins links build/plugins).
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    path.push_back(
        (exe.parent_path() / ".." / "lib" / "flipper" / "plugins").lexically_normal().string());
  return path;
}

LoadedPlugin PluginLoader::open(const std::string& name, sdk::PluginKind kind) const {
  const std::string kind_str = sdk::kind_name(kind);
  const PluginEntry* found = nullptr;
  for (const auto& e : entries_)
    if (e.name == name && e.shadowed_by.empty()) {
      found = &e;
      break;
    }
  if (found == nullptr || (!found->kind.empty() && found->kind != kind_str)) {
    std::string available;
    std::string unknown_kind;
    for (const auto& e : entries_) {
      if (!e.shadowed_by.empty()) continue;
      if (e.kind == kind_str) available += (available.empty() ? "" : ", ") + e.name;
      if (e.kind.empty()) unknown_kind += (unknown_kind.empty() ? "" : ", ") + e.name;
    }
    std::string searched;
    for (const auto& d : search_path_) searched += (searched.empty() ? "" : ", ") + d;
    std::string reason = found == nullptr
                             ? "no " + kind_str + " plugin named '" + name + "'"
                             : "plugin '" + name + "' (" + found->library + ") is a " +
                                   found->kind + " plugin, not a " + kind_str + " plugin";
    throw Error(codes::kPluginNotFound,
                reason + "; available " + kind_str +
                    " plugins: " + (available.empty() ? "none" : available) +
                    (unknown_kind.empty() ? "" : "; libraries without a sidecar: " + unknown_kind) +
                    "; searched: " + (searched.empty() ? "no existing directory" : searched));
  }
  return open_entry(*found, kind);
}

LoadedPlugin PluginLoader::open_entry(const PluginEntry& entry,
                                      std::optional<sdk::PluginKind> expected) const {
  const std::string who = "plugin '" + entry.name + "' (" + entry.library + ")";
  if (!entry.index_error.empty()) throw Error(codes::kPluginLoadFailed, entry.index_error);
  if (!entry.duplicate_of.empty())
    throw Error(codes::kPluginDuplicate, "plugin name '" + entry.name +
                                             "' is declared by two files: " + entry.library +
                                             " and " + entry.duplicate_of);
  // Opening, the handshake and the version checks are the SDK's host loader, shared with the
  // conformance kit; the index's own checks (kind, sidecar, name) follow.
  sdk::host::Library lib = sdk::host::open_library(entry.library);
  const FlipperPluginDescriptor* d = &sdk::host::checked_descriptor(lib, entry.name);
  const std::string dname = d->name ? d->name : "";
  if (expected && d->kind != static_cast<std::uint32_t>(*expected))
    throw Error(codes::kPluginLoadFailed, who + " is a " + kind_word(d->kind) +
                                              " plugin, but it was requested as a " +
                                              sdk::kind_name(*expected) + " plugin");
  if (!entry.kind.empty() && entry.kind != kind_word(d->kind))
    throw Error(codes::kPluginLoadFailed, who + ": the sidecar says kind '" + entry.kind +
                                              "' but the descriptor says '" + kind_word(d->kind) +
                                              "'");
  if (dname != entry.name)
    throw Error(codes::kPluginLoadFailed,
                who + ": descriptor name '" + dname + "' does not match " +
                    (entry.sidecar.empty() ? "the file name" : "the sidecar " + entry.sidecar) +
                    " ('" + entry.name + "')");
  LoadedPlugin out;
  out.entry = entry;
  out.descriptor = d;
  out.library = std::move(lib.handle);
  return out;
}

std::shared_ptr<sdk::Plugin> PluginLoader::instantiate(const LoadedPlugin& plugin,
                                                       const sdk::Params& params) const {
  sdk::Plugin* raw = nullptr;
  try {
    raw = plugin.descriptor->create(params);
  } catch (const std::exception& e) {
    throw_plugin_failure(plugin.id(), "create", e.what());
  } catch (...) {
    throw_plugin_failure(plugin.id(), "create", "unknown exception");
  }
  if (raw == nullptr) throw_plugin_failure(plugin.id(), "create", "returned null");
  // The deleter owns the library: the plugin's destroy runs while its code is still mapped.
  auto destroy = plugin.descriptor->destroy;
  return std::shared_ptr<sdk::Plugin>(raw, [library = plugin.library, destroy](sdk::Plugin* p) {
    try {
      destroy(p);
    } catch (...) {  // a destructor that throws must not take the kernel down
    }
  });
}

std::shared_ptr<sdk::Plugin> PluginLoader::create_section(const Config& config,
                                                          const std::string& section,
                                                          sdk::PluginKind kind,
                                                          PluginId* id) const {
  const LoadedPlugin plugin = open(config.plugin_name(section), kind);
  if (id != nullptr) *id = plugin.id();
  const sdk::Params params = config.plugin_params(section, plugin.schema());
  return instantiate(plugin, params);
}

}  // namespace flipper::kernel
