#pragma once
/// @file manifest.hpp
/// The parts of a run's manifest.json that say what produced it (docs/experiments.md §2): this
/// binary's build, the host, input files with their SHA-256, a config's effective text and the
/// plugins it selects (name, version, library file and its SHA-256, effective params). The
/// command that runs an experiment adds what is its own (the experiment, variants, seeds,
/// command line, times) and writes the whole with write_manifest. A re-check compares a
/// recorded manifest with the present one through provenance_warnings.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"

namespace flipper::kernel {
class PluginLoader;
}

namespace flipper::record {

/// {"flipper", "sdk", "commit", "describe", "dirty"} of this binary (build_info.hpp).
nlohmann::json build_json();
/// The source tree's commit, `git describe` and dirty state read now, by git, from `tree` (when it
/// exists and is the top of a git checkout; else "unknown"), with the build's
/// own commit and dirty state beside them: {"tree", "commit", "describe", "dirty" (yes, no or
/// unknown), "read" (how they were read), "build_commit", "build_dirty"}.
nlohmann::json source_json(const std::string& tree);
/// source_json of the source tree of the build tree this executable runs from (named by the
/// build's CMakeCache.txt beside bin/); an installed executable has none: "unknown".
nlohmann::json source_json();
/// The compiler and the library versions this binary was built against (OMPL, FCL, OctoMap,
/// Eigen, Boost, Cyclone DDS, SQLite) and the SQLite library loaded now: {"compiler", "ompl",
/// ..., "sqlite_loaded"}; "unknown" for one the build did not find.
nlohmann::json libraries_json();
/// Where a loaded plugin came from: {"dir", "in_tree" (found in the plugin folder beside the
/// executable), "shadows": [libraries of same-named plugins later on the search path that it
/// hides]}. A plugin that shadows an in-tree one is flagged by a non-empty "shadows".
nlohmann::json plugin_origin_json(const kernel::PluginLoader& loader, const std::string& library);

/// One line per plugin of a plugins_json list that shadows a same-named plugin ("plugin 'astar'
/// (/x/astar.so) shadows /build/plugins/astar.so"), for a run to say so when it starts.
std::vector<std::string> shadow_notes(const nlohmann::json& plugins);

/// This process's command line (/proc/self/cmdline) and working directory:
/// {"argv": [...], "cwd": "..."}.
nlohmann::json command_json();
/// {"name", "system", "release", "machine", "cores"}.
nlohmann::json host_json();
/// {"role", "path" (absolute), "bytes", "sha256"} of one file.
nlohmann::json file_json(const std::string& role, const std::string& path);
/// A corpus or data folder: {"path" (absolute), "files": [{"name", "bytes", "sha256"}]} for each
/// regular file directly in it, by name.
nlohmann::json folder_json(const std::string& dir);
/// A config: {"source", "base_dir", "effective" (the text `flipper config print` shows),
/// "files": [file_json of the config file, world.file and grammar.file]}.
nlohmann::json config_json(const kernel::Config& config);
/// The lexicon store a config starts from, when lexicon.path names an existing file: {"path",
/// "checksum" (of its live rules), "entry" (its last history entry), "tag" (naming that entry, or
/// null)}; null otherwise (lexicon_provenance.cpp). config_json() includes it as "lexicon".
nlohmann::json lexicon_json(const kernel::Config& config);
/// The plugins a config selects, in section order: [{"section", "name", "version", "file",
/// "sha256", "params": {name: value as text, defaults included}, "origin" (plugin_origin_json)}].
/// Opens each plugin library (checks as the kernel does); throws sdk::Error as loading would.
/// `sections` limits it to those sections (a planner benchmark records only its world and planner).
nlohmann::json plugins_json(const kernel::Config& config,
                            const std::vector<std::string>& sections = {});

/// Writes `run_dir`/manifest.json (indented; through a temporary file renamed over it, so a
/// reader never sees half a manifest). Throws sdk::Error(write_failed).
void write_manifest(const std::string& run_dir, const nlohmann::json& manifest);
/// Reads `run_dir`/manifest.json. Throws sdk::Error(bad_request) naming the file when it is
/// missing or not JSON: "RUN is not a run folder".
nlohmann::json read_manifest(const std::string& run_dir);

/// What differs between a recorded manifest and the present one that could change figures: the
/// flipper version, commit or dirty state; a plugin's name, version or file checksum; a
/// variant's effective config; an input or corpus file's checksum. One readable line each.
/// Both manifests must have the layout of docs/experiments.md §2 (build, variants[].config,
/// variants[].plugins, inputs, corpus).
std::vector<std::string> provenance_warnings(const nlohmann::json& recorded,
                                             const nlohmann::json& now);

}  // namespace flipper::record
