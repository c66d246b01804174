// Opening and checking a plugin library (flipper/sdk/host_loader.hpp): the only use of
// Boost.DLL, so a Boost upgrade touches one file.
#include "flipper/sdk/host_loader.hpp"

#define BOOST_DLL_USE_STD_FS
#include <boost/dll/shared_library.hpp>
#include <cstring>

#include "elf_check.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/version.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace host {

FlipperHandshake handshake() {
  return {FLIPPER_PLUGIN_ABI, static_cast<std::uint32_t>(sizeof(FlipperPluginDescriptor)),
          static_cast<std::uint32_t>(alignof(FlipperPluginDescriptor))};
}

Library open_library(const std::string& path) {
  namespace dll = boost::dll;
  detail::check_elf_file(path);  // a truncated file would be mapped and crash with SIGBUS
  std::shared_ptr<dll::shared_library> lib;
  try {
    lib = std::make_shared<dll::shared_library>(
        path, dll::load_mode::rtld_now | dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw Error(codes::kPluginLoadFailed, "cannot load plugin library '" + path + "': " + e.what());
  }
  Library out;
  out.path = path;
  if (lib->has(FLIPPER_PLUGIN_ENTRY_SYMBOL))
    out.entry = &lib->get<std::remove_pointer_t<FlipperPluginEntryFn>>(FLIPPER_PLUGIN_ENTRY_SYMBOL);
  out.handle = std::move(lib);
  return out;
}

const FlipperPluginDescriptor& checked_descriptor(const Library& library, const std::string& name) {
  const std::string& path = library.path;
  const std::string who = "plugin '" + name + "' (" + path + ")";
  if (library.entry == nullptr)
    throw Error(codes::kPluginLoadFailed,
                who + ": no Flipper descriptor (the library does not export " +
                    FLIPPER_PLUGIN_ENTRY_SYMBOL + "; use FLIPPER_PLUGIN in one source file)");

  // Handshake first: nothing else of the descriptor is read unless both sides agree.
  const FlipperHandshake mine = handshake();
  FlipperHandshake theirs{0, 0, 0};
  const FlipperPluginDescriptor* d = nullptr;
  try {
    d = library.entry(&mine, &theirs);
  } catch (...) {
    throw Error(codes::kPluginLoadFailed, who + ": the entry function threw");
  }
  if (theirs.abi != mine.abi)
    throw Error(codes::kPluginAbiMismatch, "Wrong API version on plugin '" + name + "' (" + path +
                                               "). Got version " + std::to_string(theirs.abi) +
                                               ", supported version is " +
                                               std::to_string(mine.abi) + ".");
  if (theirs.descriptor_size != mine.descriptor_size ||
      theirs.descriptor_align != mine.descriptor_align)
    throw Error(codes::kPluginAbiMismatch,
                "Wrong descriptor layout on plugin '" + name + "' (" + path + "). Got size " +
                    std::to_string(theirs.descriptor_size) + " align " +
                    std::to_string(theirs.descriptor_align) + ", supported size is " +
                    std::to_string(mine.descriptor_size) + " align " +
                    std::to_string(mine.descriptor_align) + ".");
  if (d == nullptr)
    throw Error(codes::kPluginAbiMismatch, who + ": the plugin refused the handshake");

  if (d->sdk_major != FLIPPER_SDK_VERSION_MAJOR || d->sdk_minor > FLIPPER_SDK_VERSION_MINOR)
    throw Error(codes::kPluginAbiMismatch,
                "Wrong SDK version on plugin '" + name + "' (" + path + "). Got version " +
                    std::to_string(d->sdk_major) + "." + std::to_string(d->sdk_minor) +
                    ", supported version is " + std::to_string(FLIPPER_SDK_VERSION_MAJOR) + "." +
                    std::to_string(FLIPPER_SDK_VERSION_MINOR) +
                    " (same major, minor at most the kernel's).");
  const char* fp = d->fingerprint ? d->fingerprint : "";
  if (std::strcmp(fp, FLIPPER_BUILD_FINGERPRINT) != 0)
    throw Error(codes::kPluginAbiMismatch, "Wrong build fingerprint on " + who + ". Got '" + fp +
                                               "', supported is '" FLIPPER_BUILD_FINGERPRINT
                                               "'. Rebuild the plugin against this SDK.");
  if (d->create == nullptr || d->destroy == nullptr || d->describe == nullptr)
    throw Error(codes::kPluginLoadFailed, who + ": the descriptor lacks create/destroy/describe");
  return *d;
}

}  // namespace host
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
