#pragma once
/// @file plugin.hpp
/// What makes a shared library a Flipper plugin: a constant, C-layout descriptor returned by one
/// exported entry function after an ABI handshake (gz-plugin's hook, LLVM's version check), and
/// the `FLIPPER_PLUGIN` macro that writes both. The descriptor is data: loading a plugin runs no
/// registration code.
///
/// Usage, in exactly one .cpp of the plugin:
/// @code
///   class AStar : public flipper::sdk::Planner {
///    public:
///     explicit AStar(const flipper::sdk::Params& p);
///     static flipper::sdk::ParamSchema schema();
///     ...
///   };
///   FLIPPER_PLUGIN(AStar, planner, "astar", "1.0.0", "Grid A* / BFS with Christofides tours")
/// @endcode

#include <cstdint>
#include <type_traits>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/params.hpp"
#include "flipper/sdk/version.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// The plugin kinds. Values are part of the ABI: never renumber, only add.
enum class PluginKind : std::uint32_t {
  world = 1,
  planner = 2,
  parser = 3,
  scorer = 4,
  rewriter = 5,
  similarity = 6,
  frontend = 7,  ///< flipper/sdk/frontend.hpp
};

/// "world", "planner", ...; "unknown" for other values.
FLIPPER_SDK_API const char* kind_name(PluginKind kind);
/// Parses a kind name; returns false if unknown.
FLIPPER_SDK_API bool parse_kind(const char* name, PluginKind& out);

/// Base of every plugin interface. Lifetime: created by the descriptor's `create`, destroyed by
/// its `destroy` (so the allocating library also frees); the kernel keeps the library loaded
/// while the object lives.
///
/// Threads: **one request at a time per instance.** A host never calls one instance from two
/// threads at once (each kernel is used by one request at a time, docs/studio.md §5; a server
/// runs a pool of kernels, each with its own instances), but it may call it from different
/// threads one after the other, and it runs *different* instances, of the same plugin too,
/// concurrently. So an instance may keep unguarded scratch state (buffers, caches) between calls,
/// without a mutex; state shared between instances (statics, globals, a shared cache) must be
/// thread-safe. The conformance kits check it: two instances answer the same requests at once on
/// two threads, and must answer as one instance does alone (flipper/testing/*_conformance.hpp).
class FLIPPER_SDK_API Plugin {
 public:
  virtual ~Plugin();
};

class World;
class Planner;
class Parser;
class Scorer;
class Rewriter;
class Similarity;

/// Maps an interface to its kind (specialised next to each interface).
template <class Interface>
struct KindOf;

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

extern "C" {

/// What each side states about itself before anything else is exchanged.
struct FlipperHandshake {
  std::uint32_t abi;
  std::uint32_t descriptor_size;
  std::uint32_t descriptor_align;
};

/// The plugin descriptor. Layout is ABI: change it only with a FLIPPER_PLUGIN_ABI bump.
struct FlipperPluginDescriptor {
  std::uint32_t abi;
  std::uint32_t sdk_major;
  std::uint32_t sdk_minor;
  std::uint32_t kind;   ///< a flipper::sdk::PluginKind value
  const char* name;     ///< stable id used in configs, e.g. "astar"
  const char* version;  ///< the plugin's own semantic version
  const char* description;
  const char* fingerprint;  ///< FLIPPER_BUILD_FINGERPRINT of the plugin's build
  void (*describe)(flipper::sdk::ParamSchema& out);
  flipper::sdk::Plugin* (*create)(const flipper::sdk::Params& params);
  void (*destroy)(flipper::sdk::Plugin* plugin);
  const void* reserved[4];
};

/// Signature of the exported entry `flipper_plugin_entry`. The plugin writes its own handshake
/// into `plugin` and returns its descriptor only if `kernel` matches it exactly; otherwise null.
typedef const FlipperPluginDescriptor* (*FlipperPluginEntryFn)(const FlipperHandshake* kernel,
                                                               FlipperHandshake* plugin);
}

/// The exported symbol name of the entry function.
#define FLIPPER_PLUGIN_ENTRY_SYMBOL "flipper_plugin_entry"

/// Declares the plugin class `Class` (which must derive from the interface of `kind` and provide
/// `Class(const flipper::sdk::Params&)` and `static flipper::sdk::ParamSchema schema()`).
/// `kind` is one of: world, planner, parser, scorer, rewriter, similarity. Pass
/// FLIPPER_PLUGIN_VERSION as `version`: flipper_add_plugin(... VERSION v) defines it, so the
/// descriptor and the sidecar state one version.
#define FLIPPER_PLUGIN(Class, kind, name, version, description)                                \
  namespace {                                                                                  \
  void flipper_plugin_describe_(::flipper::sdk::ParamSchema& out) {                            \
    out = Class::schema();                                                                     \
  }                                                                                            \
  ::flipper::sdk::Plugin* flipper_plugin_create_(const ::flipper::sdk::Params& params) {       \
    return new Class(params);                                                                  \
  }                                                                                            \
  void flipper_plugin_destroy_(::flipper::sdk::Plugin* plugin) {                               \
    delete plugin;                                                                             \
  }                                                                                            \
  const FlipperPluginDescriptor flipper_plugin_descriptor_ = {                                 \
      FLIPPER_PLUGIN_ABI,                                                                      \
      FLIPPER_SDK_VERSION_MAJOR,                                                               \
      FLIPPER_SDK_VERSION_MINOR,                                                               \
      static_cast<std::uint32_t>(::flipper::sdk::PluginKind::kind),                            \
      name,                                                                                    \
      version,                                                                                 \
      description,                                                                             \
      FLIPPER_BUILD_FINGERPRINT,                                                               \
      &flipper_plugin_describe_,                                                               \
      &flipper_plugin_create_,                                                                 \
      &flipper_plugin_destroy_,                                                                \
      {nullptr, nullptr, nullptr, nullptr}};                                                   \
  }                                                                                            \
  static_assert(::flipper::sdk::KindOf<typename Class::Interface>::value ==                    \
                    ::flipper::sdk::PluginKind::kind,                                          \
                "FLIPPER_PLUGIN: the class does not implement the interface of this kind");    \
  extern "C" FLIPPER_PLUGIN_EXPORT const FlipperPluginDescriptor* flipper_plugin_entry(        \
      const FlipperHandshake* kernel, FlipperHandshake* plugin) {                              \
    const FlipperHandshake mine{FLIPPER_PLUGIN_ABI,                                            \
                                static_cast<std::uint32_t>(sizeof(FlipperPluginDescriptor)),   \
                                static_cast<std::uint32_t>(alignof(FlipperPluginDescriptor))}; \
    if (plugin != nullptr) *plugin = mine;                                                     \
    if (kernel == nullptr || kernel->abi != mine.abi ||                                        \
        kernel->descriptor_size != mine.descriptor_size ||                                     \
        kernel->descriptor_align != mine.descriptor_align)                                     \
      return nullptr;                                                                          \
    return &flipper_plugin_descriptor_;                                                        \
  }
