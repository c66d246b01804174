#pragma once
/// @file plugin_factory.hpp
/// Creating a built plugin for a test, the way the kernel creates it (header-only, no Catch2):
/// the library is opened by the SDK's host loader (flipper/sdk/host_loader.hpp: ELF check,
/// handshake, SDK version, fingerprint), the parameters are validated against the plugin's
/// schema by sdk::validate_params (defaults filled in, unknown keys and bad values refused with
/// the kernel's messages), and the object must implement the interface asked for. The factory
/// the per-kind kits take is then one line:
/// @code
///   FLIPPER_PLANNER_CONFORMANCE("astar", [] { return load_plugin<sdk::Planner>("astar"); })
/// @endcode
/// A name is looked up as `<FLIPPER_PLUGIN_DIR>/<name>.so` (flipper_add_conformance_test defines
/// FLIPPER_PLUGIN_DIR as the plugin's output directory); anything with a '/' is a path.

#include <cstdint>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/host_loader.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::testing {

/// Parameter values by name, as a config's `<section>.params` gives them.
using ParamValues = std::map<std::string, sdk::ParamValue>;

/// A plugin library opened by the SDK's host loader, exactly as the kernel opens it, with its
/// descriptor.
struct PluginLibrary {
  sdk::host::Library library;
  FlipperPluginEntryFn entry = nullptr;

  explicit PluginLibrary(const std::string& path)
      : library(sdk::host::open_library(path)), entry(library.entry) {}
  static FlipperHandshake kernel_handshake() { return sdk::host::handshake(); }
  /// The descriptor after a matching handshake (null if the plugin refuses).
  const FlipperPluginDescriptor* descriptor() const {
    const FlipperHandshake mine = kernel_handshake();
    FlipperHandshake theirs{};
    return entry ? entry(&mine, &theirs) : nullptr;
  }
  /// The descriptor after every check of the host loader (throws sdk::Error otherwise).
  const FlipperPluginDescriptor& checked(const std::string& name) const {
    return sdk::host::checked_descriptor(library, name);
  }
  sdk::ParamSchema schema() const {
    sdk::ParamSchema s;
    checked(library.path).describe(s);
    return s;
  }
  /// Creates an object whose deleter keeps the library loaded.
  std::shared_ptr<sdk::Plugin> create(const sdk::Params& params) const {
    const FlipperPluginDescriptor* d = descriptor();
    sdk::Plugin* raw = d->create(params);
    return std::shared_ptr<sdk::Plugin>(
        raw, [lib = library.handle, destroy = d->destroy](sdk::Plugin* p) { destroy(p); });
  }
  /// Creates the plugin with `params` as they are (not validated) as an `Interface`; throws
  /// std::runtime_error when the plugin is of another kind.
  template <class Interface>
  std::shared_ptr<Interface> create_as(const sdk::Params& params) const {
    const FlipperPluginDescriptor& d = checked(library.path);
    if (d.kind != static_cast<std::uint32_t>(sdk::KindOf<Interface>::value))
      throw std::runtime_error("plugin " + library.path + " is a " +
                               sdk::kind_name(static_cast<sdk::PluginKind>(d.kind)) +
                               " plugin, not a " + sdk::kind_name(sdk::KindOf<Interface>::value));
    std::shared_ptr<sdk::Plugin> object = create(params);
    auto* typed = dynamic_cast<Interface*>(object.get());
    if (typed == nullptr)
      throw std::runtime_error("plugin " + library.path + " does not implement its interface");
    return std::shared_ptr<Interface>(object, typed);  // shares the owner: destroyed through it
  }
};

#ifdef FLIPPER_PLUGIN_DIR
inline std::string default_plugin_dir() {
  return FLIPPER_PLUGIN_DIR;
}
#else
inline std::string default_plugin_dir() {
  return ".";
}
#endif

/// The library of a plugin name (`<dir>/<name>.so`) or a path (anything with a '/').
inline std::string plugin_path(const std::string& name_or_path,
                               const std::string& dir = default_plugin_dir()) {
  return name_or_path.find('/') != std::string::npos ? name_or_path
                                                     : dir + "/" + name_or_path + ".so";
}

/// The plugin as the kernel would create it from `<section>.params: given`.
template <class Interface>
std::shared_ptr<Interface> load_plugin(const std::string& name_or_path,
                                       const ParamValues& given = {}) {
  const PluginLibrary lib(plugin_path(name_or_path));
  const sdk::Params params = sdk::validate_params(lib.schema(), given, name_or_path + ".params");
  return lib.create_as<Interface>(params);
}

/// Parameter values from `name=value` texts, typed by the schema as a config's YAML scalars
/// would be: bool `true`/`false`, numbers, lists `a,b` (or `[a, b]`), anything else verbatim.
/// A name the schema lacks is kept as a string, so validation names it.
inline ParamValues param_values(const sdk::ParamSchema& schema,
                                const std::vector<std::string>& settings) {
  ParamValues out;
  for (const std::string& s : settings) {
    const auto eq = s.find('=');
    if (eq == std::string::npos)
      throw sdk::Error(sdk::codes::kBadConfig, "parameter setting '" + s + "' is not name=value");
    const std::string name = s.substr(0, eq), text = s.substr(eq + 1);
    const sdk::ParamSpec* spec = schema.find(name);
    const sdk::ParamType type = spec != nullptr ? spec->type : sdk::ParamType::String;
    auto list = [&] {
      std::string inner = text;
      if (inner.size() >= 2 && inner.front() == '[' && inner.back() == ']')
        inner = inner.substr(1, inner.size() - 2);
      std::vector<std::string> items;
      std::stringstream in(inner);
      for (std::string item; std::getline(in, item, ',');) {
        const auto b = item.find_first_not_of(' '), e = item.find_last_not_of(' ');
        if (b != std::string::npos) items.push_back(item.substr(b, e - b + 1));
      }
      return items;
    };
    try {
      switch (type) {
        case sdk::ParamType::Bool:
          out[name] = text == "true";
          if (text != "true" && text != "false") out[name] = text;
          break;
        case sdk::ParamType::Int:
          out[name] = static_cast<std::int64_t>(std::stoll(text));
          break;
        case sdk::ParamType::Double:
          out[name] = std::stod(text);
          break;
        case sdk::ParamType::StringList:
        case sdk::ParamType::PathList:
          out[name] = list();
          break;
        case sdk::ParamType::DoubleList: {
          std::vector<double> numbers;
          for (const std::string& item : list()) numbers.push_back(std::stod(item));
          out[name] = std::move(numbers);
          break;
        }
        default:
          out[name] = text;
      }
    } catch (const std::logic_error&) {  // not a number: validation says what is wrong
      out[name] = text;
    }
  }
  return out;
}

}  // namespace flipper::testing
