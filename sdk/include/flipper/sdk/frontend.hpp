#pragma once
/// @file frontend.hpp
/// Front ends as plugins (docs/architecture.md §1 "Front ends are modules"): a front end is a
/// plugin of kind `frontend` that `flipper` loads with the same loader as every other plugin
/// (sidecar, ABI handshake, version and fingerprint checks, the same refusal messages) and runs
/// on a host. It declares its name and version in its descriptor, its parameters (its config
/// schema fragment) with `schema()`, and `run`. The host gives it sessions and answers
/// session-protocol requests (docs/protocol.md, the one contract of every front end): a front
/// end is a transport, never a second implementation of the protocol.
///
/// Usage, in exactly one .cpp of the front end (examples/out-of-tree-frontend):
/// @code
///   class Lines : public flipper::sdk::Frontend {
///    public:
///     explicit Lines(const flipper::sdk::Params& p);
///     static flipper::sdk::ParamSchema schema();
///     int run(flipper::sdk::FrontendHost& host) override;
///   };
///   FLIPPER_FRONTEND(Lines, "lines", FLIPPER_PLUGIN_VERSION, "Session protocol over TCP lines")
/// @endcode

#include <cstdint>
#include <string>

#include "flipper/sdk/plugin.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// The plugin kind of a front end: PluginKind::frontend (7), the name front ends were built
/// with before the enumerator existed (docs/sdk-migration.md 3.0.0).
inline constexpr PluginKind kFrontendKind = PluginKind::frontend;

/// What `flipper` gives a running front end. Thread rule: the host serialises the requests of
/// all sessions itself, so a front end may call it from any of its threads.
class FLIPPER_SDK_API FrontendHost {
 public:
  using SessionId = std::uint64_t;

  virtual ~FrontendHost();

  /// Opens a session on the config's runtime (world, plugins, lexicon). The first call builds
  /// the runtime; a bad config throws Error(bad_config) naming the key.
  virtual SessionId open_session() = 0;
  /// Answers one session-protocol request line (JSON, docs/protocol.md) of `session`: exactly
  /// one answer line without its newline; empty for a request that has no answer. A request
  /// longer than the session's input.max_line_bytes is answered with the protocol's error.
  /// An unknown session throws Error(bad_request).
  virtual std::string handle(SessionId session, const std::string& request) = 0;
  /// Ends a session (its state is dropped; what it taught the lexicon stays).
  virtual void close_session(SessionId session) = 0;
  /// True once the front end should stop (SIGINT or SIGTERM to flipper).
  virtual bool stopping() const = 0;
  /// One line on flipper's standard error, prefixed with "flipper <command>: ".
  virtual void log(const std::string& line) = 0;
  /// What a front end built in the same tree as this very flipper may use beyond this
  /// interface (`tag` names the hand-over's version); null for any other tag. Out-of-tree
  /// front ends never need it.
  virtual void* internals(const char* tag) = 0;
};

/// A front end: constructed with its validated parameters, then run once until it stops.
class FLIPPER_SDK_API Frontend : public Plugin {
 public:
  using Interface = Frontend;
  /// Serves until `host.stopping()` (or its own end); returns the process's exit status
  /// (0: stopped normally). Errors it cannot answer itself are thrown as sdk::Error.
  virtual int run(FrontendHost& host) = 0;
};

template <>
struct KindOf<Frontend> {
  static constexpr PluginKind value = PluginKind::frontend;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk

/// FLIPPER_PLUGIN for a front end (`Class` derives from flipper::sdk::Frontend and provides
/// `Class(const flipper::sdk::Params&)` and `static flipper::sdk::ParamSchema schema()`).
#define FLIPPER_FRONTEND(Class, name, version, description)                                    \
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
      static_cast<std::uint32_t>(::flipper::sdk::PluginKind::frontend),                        \
      name,                                                                                    \
      version,                                                                                 \
      description,                                                                             \
      FLIPPER_BUILD_FINGERPRINT,                                                               \
      &flipper_plugin_describe_,                                                               \
      &flipper_plugin_create_,                                                                 \
      &flipper_plugin_destroy_,                                                                \
      {nullptr, nullptr, nullptr, nullptr}};                                                   \
  }                                                                                            \
  static_assert(std::is_base_of_v<::flipper::sdk::Frontend, Class>,                            \
                "FLIPPER_FRONTEND: the class does not implement flipper::sdk::Frontend");      \
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
