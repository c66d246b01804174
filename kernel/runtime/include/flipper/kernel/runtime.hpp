#pragma once
/// @file runtime.hpp
/// A runtime is everything a config selects, loaded and ready: one instance of each plugin kind
/// (through the loader, libraries kept loaded while the objects live), the core grammar handed to
/// the parser, and the default world. Built once, before the first request is answered.
/// Every plugin is held as a PluginRef: calls into it go through `ref.call(op, f)`, which names
/// the plugin the same way in every error (plugin_ref.hpp).

#include <memory>
#include <string>
#include <utility>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/kernel/usage_table.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/sdk/scorer.hpp"
#include "flipper/sdk/similarity.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::kernel {

struct Runtime {
  explicit Runtime(Config c) : config(std::move(c)) {}

  Config config;
  PluginRef<sdk::World> world;
  PluginRef<sdk::Planner> planner;
  PluginRef<sdk::Parser> parser;
  PluginRef<sdk::Scorer> scorer;
  PluginRef<sdk::Rewriter> rewriter;      ///< empty when the config has no rewriter
  PluginRef<sdk::Similarity> similarity;  ///< empty when the config has no similarity
  std::shared_ptr<const sdk::Grammar> core_grammar;
  sdk::WorldState default_world;  ///< from world.file (loaded by the world plugin)
  /// Use counters of induced rules, shared by every session of this runtime; scorers read them
  /// through ScoreContext::usage.
  std::shared_ptr<UsageTable> usage = std::make_shared<UsageTable>();
};

/// What `plugins.isolation: auto` means for the runtimes this process builds from now on:
/// `process` in the servers (serve, dds: each calls this before building its runtimes, since a
/// crash there would lose other users' work), `in_process` (the initial value) elsewhere
/// (docs/plugins-untrusted.md §6). The servers' AddressSanitizer builds do not call it: that
/// allocator is not safe to fork from a busy process (apps/cli/sanitizer_build.hpp).
void set_auto_isolation(Isolation isolation);

/// Loads every plugin the config selects and builds the runtime. Throws sdk::Error with codes
/// bad_config, plugin_not_found, plugin_abi_mismatch, plugin_load_failed, plugin_error,
/// bad_world, bad_grammar; messages name the plugin, file and what was expected.
std::unique_ptr<Runtime> make_runtime(const Config& config);

/// Loads a world file (or JSON text) with the runtime's world plugin. A file must be a regular
/// file of at most input.max_file_bytes (not_a_regular_file, file_too_large).
sdk::WorldState load_world_file(const Runtime& rt, const std::string& path);

/// Loads world JSON text with the runtime's world plugin, which reads it once within the limits
/// world.max_cells and input.max_file_bytes (world_too_large before it allocates the cells; the
/// result is checked again). A world of the other dimensions names the plugins that read it,
/// from their sidecars (docs/worlds.md). `base_dir` resolves the world's own file references.
sdk::WorldState load_world_text(const Runtime& rt, const std::string& text,
                                const std::string& base_dir);

}  // namespace flipper::kernel
