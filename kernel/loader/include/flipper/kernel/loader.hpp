#pragma once
/// @file loader.hpp
/// Plugin discovery and loading. Discovery indexes `*.flipper.yaml` sidecars (and bare `*.so`
/// files) along a search path without running plugin code; loading opens only the library the
/// config selects (rtld_now | rtld_local), performs the ABI handshake, then checks SDK version,
/// build fingerprint, kind and name. Every failure is an sdk::Error naming the file(s) and the
/// values involved; a bad plugin never crashes the kernel.
///
/// Name resolution follows PATH semantics: the first search directory that has a plugin of that
/// name wins (later ones are listed as shadowed); two files declaring one name in the same
/// directory are a plugin_duplicate error.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::kernel {

/// What the index knows about a plugin file before loading it.
struct PluginEntry {
  std::string name;          ///< sidecar name, or the file stem of a bare .so
  std::string kind;          ///< sidecar kind; empty for a bare .so (known after loading)
  std::string version;       ///< sidecar version; empty for a bare .so
  int dims = 0;              ///< a world plugin's sidecar `dims` (2 or 3); 0 when not declared
  std::string library;       ///< absolute path of the .so
  std::string sidecar;       ///< absolute path of the sidecar; empty when none
  std::string dir;           ///< the search directory it was found in
  std::string shadowed_by;   ///< library of a same-named plugin in an earlier directory
  std::string duplicate_of;  ///< library of another file in the same directory with this name
  std::string index_error;   ///< a broken sidecar: why
};

/// A library that passed every check. Copies share the library handle.
struct LoadedPlugin {
  PluginEntry entry;
  const FlipperPluginDescriptor* descriptor = nullptr;
  std::shared_ptr<void> library;  ///< keeps the code mapped while anything refers to it

  /// "name (path)" for messages.
  std::string label() const;
  /// Kind, name and file, as PluginRef messages name the plugin.
  PluginId id() const;
  /// The declared parameter schema (plugin call, guarded: failures become plugin_error).
  sdk::ParamSchema schema() const;
};

class PluginLoader {
 public:
  /// Indexes the directories (missing ones are skipped) in order.
  explicit PluginLoader(const std::vector<std::string>& search_path);

  /// The search path for a config: `plugin_paths`, then $FLIPPER_PLUGIN_PATH (colon-separated),
  /// then `<exe>/../lib/flipper/plugins` (the install layout; the build tree mirrors it).
  static std::vector<std::string> search_path_for(const Config& config);

  const std::vector<std::string>& search_path() const { return search_path_; }
  /// Every indexed file, in search order then file name.
  const std::vector<PluginEntry>& entries() const { return entries_; }

  /// Opens and checks the plugin `name`, which must be of `kind`. Throws plugin_not_found
  /// (listing the available plugins of that kind), plugin_duplicate, plugin_load_failed,
  /// plugin_abi_mismatch.
  LoadedPlugin open(const std::string& name, sdk::PluginKind kind) const;
  /// Opens and checks one indexed file; `expected` null accepts any kind.
  LoadedPlugin open_entry(const PluginEntry& entry, std::optional<sdk::PluginKind> expected) const;

  /// Constructs an object (plugin call, guarded: a throwing constructor becomes plugin_error
  /// "plugin 'x' (path): create: <message>"). The returned pointer owns the library handle, so the
  /// object is destroyed by the plugin's `destroy` before its code can be unmapped.
  std::shared_ptr<sdk::Plugin> instantiate(const LoadedPlugin& plugin,
                                           const sdk::Params& params) const;

  /// The plugin a config section selects ("planner"), with its params validated against the
  /// plugin's schema before construction.
  /// `id`, when given, receives the plugin's identity.
  std::shared_ptr<sdk::Plugin> create_section(const Config& config, const std::string& section,
                                              sdk::PluginKind kind, PluginId* id = nullptr) const;
  /// The same, typed, as the handle every call into it goes through.
  template <class Interface>
  PluginRef<Interface> create(const Config& config, const std::string& section) const {
    PluginId id;
    std::shared_ptr<sdk::Plugin> object =
        create_section(config, section, sdk::KindOf<Interface>::value, &id);
    auto* typed = dynamic_cast<Interface*>(object.get());
    if (typed == nullptr)
      throw sdk::Error(sdk::codes::kPluginLoadFailed,
                       id.label() + " does not implement the " + section + " interface");
    return PluginRef<Interface>(std::shared_ptr<Interface>(std::move(object), typed),
                                std::move(id));
  }

 private:
  std::vector<std::string> search_path_;
  std::vector<PluginEntry> entries_;
};

}  // namespace flipper::kernel
