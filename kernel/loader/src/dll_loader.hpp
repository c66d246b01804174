#pragma once
// The only seam to Boost.DLL (dll_loader.cpp), so a Boost upgrade touches one file.
#include <memory>
#include <string>

#include "flipper/sdk/plugin.hpp"

namespace flipper::kernel::detail {

struct OpenedLibrary {
  std::shared_ptr<void> handle;          ///< owns the boost::dll::shared_library
  FlipperPluginEntryFn entry = nullptr;  ///< null: the library exports no Flipper entry
};

/// dlopen with rtld_now | rtld_local. Throws sdk::Error(plugin_load_failed) with the loader's
/// reason (missing file, unresolved symbol...).
OpenedLibrary open_library(const std::string& path);

/// Absolute path of the running executable.
std::string executable_path();

}  // namespace flipper::kernel::detail
