#pragma once
// Test support: loads a built in-tree plugin straight from build/plugins/<name>.so through the
// conformance kit's factory (flipper/testing/plugin_factory.hpp: the SDK's host loader, the
// kernel's own way of opening and checking a library, without the kernel's index or config) so
// tests of one component do not depend on the whole kernel. Unlike testing::load_plugin, the
// params are not validated: what a test sets is passed as it is, the schema's defaults fill the
// rest. The returned shared_ptr keeps the library loaded.
#include <memory>
#include <string>

#include "flipper/testing/plugin_factory.hpp"

namespace flipper::testsupport {

template <class Interface>
std::shared_ptr<Interface> load_plugin(const std::string& name, const sdk::Params& params = {},
                                       const std::string& dir = FLIPPER_PLUGIN_DIR) {
  const testing::PluginLibrary lib(testing::plugin_path(name, dir));
  sdk::Params full = params;
  for (const auto& spec : lib.schema().params)
    if (!full.has(spec.name) && spec.default_value) full.set(spec.name, *spec.default_value);
  return lib.create_as<Interface>(full);
}

}  // namespace flipper::testsupport
