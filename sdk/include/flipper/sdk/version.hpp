#pragma once
/// @file version.hpp
/// Two numbers guard compatibility between the kernel and a plugin:
/// - FLIPPER_PLUGIN_ABI: an integer bumped whenever the descriptor layout or any interface vtable
///   changes (virtual functions added, removed or reordered), as LLVM does for pass plugins.
/// - The SDK semantic version: a plugin must have the same major, and its minor must be at most
///   the kernel's (a plugin built against a newer SDK minor may use what the kernel lacks).
/// Plus a build fingerprint (compiler, libstdc++ ABI, Boost and Eigen versions) that Boost.DLL
/// itself does not check: a mismatch there would crash instead of failing cleanly.
///
///
/// What changed in each version, and what a plugin author does about it: docs/sdk-migration.md.

#include <boost/version.hpp>

#define FLIPPER_PLUGIN_ABI 3
#define FLIPPER_SDK_VERSION_MAJOR 2
#define FLIPPER_SDK_VERSION_MINOR 3
#define FLIPPER_SDK_VERSION_PATCH 0

#define FLIPPER_STRINGIFY_IMPL(x) #x
#define FLIPPER_STRINGIFY(x) FLIPPER_STRINGIFY_IMPL(x)

#ifndef _GLIBCXX_USE_CXX11_ABI
#define FLIPPER_CXX11_ABI_VALUE 0
#else
#define FLIPPER_CXX11_ABI_VALUE _GLIBCXX_USE_CXX11_ABI
#endif

/// Build fingerprint compared by the loader; any difference refuses the plugin.
#define FLIPPER_BUILD_FINGERPRINT \
  "gcc" FLIPPER_STRINGIFY(__GNUC__) ";cxx11abi=" FLIPPER_STRINGIFY(              \
      FLIPPER_CXX11_ABI_VALUE) ";boost=" FLIPPER_STRINGIFY(BOOST_VERSION) ";cxx" \
                                                                          "=" FLIPPER_STRINGIFY(__cplusplus)

namespace flipper::sdk {
inline namespace v1 {
struct SdkVersion {
  int major;
  int minor;
  int patch;
};
constexpr SdkVersion kSdkVersion{FLIPPER_SDK_VERSION_MAJOR, FLIPPER_SDK_VERSION_MINOR,
                                 FLIPPER_SDK_VERSION_PATCH};
}  // namespace v1
}  // namespace flipper::sdk
