#pragma once
/// @file host_loader.hpp
/// The one way a host opens a plugin library. The kernel's loader, the conformance kit
/// (flipper/testing/loader.hpp) and the tests' plugin fixture all go through it, so a plugin is
/// loaded the same way everywhere (the ELF file checked before it is mapped, rtld_now |
/// rtld_local) and refused for the same reasons with the same messages (docs/architecture.md §5).

#include <memory>
#include <string>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/params.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace host {

/// The handshake this SDK build offers a plugin.
FLIPPER_SDK_API FlipperHandshake handshake();

/// An opened plugin library. Copies share the handle; the code stays mapped while one exists.
struct Library {
  std::string path;
  std::shared_ptr<void> handle;
  FlipperPluginEntryFn entry = nullptr;  ///< null: the library exports no Flipper entry
};

/// Checks the ELF file, then opens it with rtld_now | rtld_local. Throws
/// Error(plugin_load_failed) naming the file and the reason.
FLIPPER_SDK_API Library open_library(const std::string& path);

/// The descriptor of an opened library after the handshake (ABI number, descriptor layout) and
/// the version checks (SDK major equal, minor at most this SDK's; the build fingerprint), with
/// create, destroy and describe present. `name` is what messages call the plugin: "plugin
/// 'name' (path)". Throws Error(plugin_load_failed | plugin_abi_mismatch).
FLIPPER_SDK_API const FlipperPluginDescriptor& checked_descriptor(const Library& library,
                                                                  const std::string& name);

}  // namespace host
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
