#pragma once
// Test support: loads a built in-tree plugin straight from build/plugins/<name>.so through the
// SDK's host loader (the kernel's own way of opening and checking a library, without the
// kernel's index or config) so tests of one component do not depend on the whole kernel. The
// returned shared_ptr keeps the library loaded.
#include <memory>
#include <stdexcept>
#include <string>

#include "flipper/sdk/host_loader.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::testsupport {

template <class Interface>
std::shared_ptr<Interface> load_plugin(const std::string& name, const sdk::Params& params = {},
                                       const std::string& dir = FLIPPER_PLUGIN_DIR) {
  const sdk::host::Library lib = sdk::host::open_library(dir + "/" + name + ".so");
  const FlipperPluginDescriptor* d = &sdk::host::checked_descriptor(lib, name);
  if (d->kind != static_cast<std::uint32_t>(sdk::KindOf<Interface>::value))
    throw std::runtime_error("plugin " + name + " is not of the requested kind");
  // Fill defaults from the schema for parameters the test did not set.
  sdk::ParamSchema schema;
  d->describe(schema);
  sdk::Params full = params;
  for (const auto& spec : schema.params)
    if (!full.has(spec.name) && spec.default_value) full.set(spec.name, *spec.default_value);
  sdk::Plugin* raw = d->create(full);
  auto* typed = dynamic_cast<Interface*>(raw);
  if (typed == nullptr) {
    d->destroy(raw);
    throw std::runtime_error("plugin " + name + " does not implement the interface");
  }
  auto destroy = d->destroy;
  // The deleter owns the library: the object is destroyed before the library can go away.
  return std::shared_ptr<Interface>(typed,
                                    [handle = lib.handle, destroy, raw](Interface*) { destroy(raw); });
}

}  // namespace flipper::testsupport
