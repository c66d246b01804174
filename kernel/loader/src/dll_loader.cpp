#include "dll_loader.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include "elf_check.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel::detail {

OpenedLibrary open_library(const std::string& path) {
  namespace dll = boost::dll;
  std::shared_ptr<dll::shared_library> lib;
  check_elf_file(path);  // a truncated file would be mapped and crash with SIGBUS
  try {
    lib = std::make_shared<dll::shared_library>(
        path, dll::load_mode::rtld_now | dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw sdk::Error(sdk::codes::kPluginLoadFailed,
                     "cannot load plugin library '" + path + "': " + e.what());
  }
  OpenedLibrary out;
  if (lib->has(FLIPPER_PLUGIN_ENTRY_SYMBOL))
    out.entry = &lib->get<std::remove_pointer_t<FlipperPluginEntryFn>>(FLIPPER_PLUGIN_ENTRY_SYMBOL);
  out.handle = std::move(lib);
  return out;
}

std::string executable_path() {
  boost::dll::fs::error_code ec;
  const auto p = boost::dll::program_location(ec);
  return ec ? std::string() : p.string();
}

}  // namespace flipper::kernel::detail
