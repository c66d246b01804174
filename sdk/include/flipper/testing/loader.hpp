#pragma once
/// @file loader.hpp
/// Conformance kit, loader layer (header-only, Catch2 v2): checks a *built* plugin library the way
/// the kernel will load it. Use it through CMake, which injects the path (and runs the kit of the
/// plugin's kind too, cmake/FlipperTesting.cmake):
/// @code
///   flipper_add_conformance_test(astar)          # in plugins/astar/CMakeLists.txt
/// @endcode
/// or by hand in a test source: `FLIPPER_LOADER_CONFORMANCE("/path/to/astar.so")`.
/// Checks: the descriptor is exported; the handshake succeeds and a mismatching kernel is
/// refused; SDK version, fingerprint, kind and name are sane; the schema is listable and its
/// defaults pass validation; an unknown key is rejected by the kernel's validation
/// (flipper::sdk::validate_params); 100 create/destroy cycles work.
///
/// The library is opened by the SDK's host loader (flipper/sdk/host_loader.hpp), the one the
/// kernel uses, and must pass its checks (handshake, SDK version, fingerprint) before the
/// kit's own.

#include <catch2/catch.hpp>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/frontend.hpp"
#include "flipper/sdk/host_loader.hpp"
#include "flipper/sdk/param_check.hpp"
#include "flipper/sdk/sdk.hpp"
#include "flipper/testing/plugin_factory.hpp"

namespace flipper::testing {

/// Whether `object` implements the interface of `kind` (dynamic_cast across the boundary works
/// only if the SDK's typeinfo is shared, which is what this also checks).
inline bool implements_kind(const sdk::Plugin* object, std::uint32_t kind) {
  switch (static_cast<sdk::PluginKind>(kind)) {
    case sdk::PluginKind::world:
      return dynamic_cast<const sdk::World*>(object) != nullptr;
    case sdk::PluginKind::planner:
      return dynamic_cast<const sdk::Planner*>(object) != nullptr;
    case sdk::PluginKind::parser:
      return dynamic_cast<const sdk::Parser*>(object) != nullptr;
    case sdk::PluginKind::scorer:
      return dynamic_cast<const sdk::Scorer*>(object) != nullptr;
    case sdk::PluginKind::rewriter:
      return dynamic_cast<const sdk::Rewriter*>(object) != nullptr;
    case sdk::PluginKind::similarity:
      return dynamic_cast<const sdk::Similarity*>(object) != nullptr;
    case sdk::PluginKind::frontend:
      return dynamic_cast<const sdk::Frontend*>(object) != nullptr;
  }
  return false;
}

/// The loader-layer checks. `given` supplies values for required parameters (others default).
inline void check_loader_conformance(const std::string& path,
                                     const std::map<std::string, sdk::ParamValue>& given = {}) {
  INFO("plugin library: " << path);
  PluginLibrary lib(path);

  // Descriptor present, and the host loader's checks pass (what the kernel requires to load it).
  REQUIRE(lib.entry != nullptr);
  REQUIRE_NOTHROW(sdk::host::checked_descriptor(lib.library, path));

  // Handshake: the plugin states its own values and accepts exactly the kernel's.
  const FlipperHandshake mine = PluginLibrary::kernel_handshake();
  FlipperHandshake theirs{};
  const FlipperPluginDescriptor* d = lib.entry(&mine, &theirs);
  REQUIRE(d != nullptr);
  CHECK(theirs.abi == mine.abi);
  CHECK(theirs.descriptor_size == mine.descriptor_size);
  CHECK(theirs.descriptor_align == mine.descriptor_align);
  FlipperHandshake future = mine;
  future.abi = mine.abi + 1;
  CHECK(lib.entry(&future, &theirs) == nullptr);
  CHECK(lib.entry(nullptr, &theirs) == nullptr);

  // Versions, fingerprint, identity.
  CHECK(d->abi == FLIPPER_PLUGIN_ABI);
  CHECK(d->sdk_major == FLIPPER_SDK_VERSION_MAJOR);
  CHECK(d->sdk_minor <= FLIPPER_SDK_VERSION_MINOR);
  REQUIRE(d->fingerprint != nullptr);
  CHECK(std::string(d->fingerprint) == FLIPPER_BUILD_FINGERPRINT);
  REQUIRE(d->name != nullptr);
  CHECK(std::strlen(d->name) > 0);
  REQUIRE(d->version != nullptr);
  CHECK(std::string(sdk::kind_name(static_cast<sdk::PluginKind>(d->kind))) != "unknown");
  REQUIRE(d->describe != nullptr);
  REQUIRE(d->create != nullptr);
  REQUIRE(d->destroy != nullptr);

  // Schema: listable without an instance, unique names, defaults that pass validation.
  sdk::ParamSchema schema;
  REQUIRE_NOTHROW(d->describe(schema));
  std::set<std::string> names;
  for (const auto& p : schema.params) {
    CHECK(!p.name.empty());
    CHECK(names.insert(p.name).second);
  }
  sdk::Params params;
  REQUIRE_NOTHROW(params = sdk::validate_params(schema, given, std::string(d->name) + ".params"));

  // An unknown key is rejected by the kernel's validation, naming the key.
  auto with_unknown = given;
  with_unknown["no_such_parameter_xyz"] = std::string("1");
  try {
    (void)sdk::validate_params(schema, with_unknown, "plugin.params");
    FAIL("an unknown parameter key was accepted");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kBadConfig);
    CHECK(std::string(e.what()).find("no_such_parameter_xyz") != std::string::npos);
  }

  // 100 create/destroy cycles through the descriptor; each object implements its kind.
  for (int i = 0; i < 100; ++i) {
    auto object = lib.create(params);
    REQUIRE(object != nullptr);
    REQUIRE(implements_kind(object.get(), d->kind));
  }
}

}  // namespace flipper::testing

/// Registers the loader-layer conformance test for the plugin library at `path`.
#define FLIPPER_LOADER_CONFORMANCE(path)                            \
  TEST_CASE("loader conformance: " path, "[conformance][loader]") { \
    ::flipper::testing::check_loader_conformance(path);             \
  }
/// Same, with values for required parameters: a std::map<std::string, sdk::ParamValue>.
#define FLIPPER_LOADER_CONFORMANCE_WITH(path, params)               \
  TEST_CASE("loader conformance: " path, "[conformance][loader]") { \
    ::flipper::testing::check_loader_conformance(path, params);     \
  }
