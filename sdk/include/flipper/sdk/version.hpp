#pragma once
/// @file version.hpp
/// What guards compatibility between the kernel and a plugin (docs/sdk-migration.md):
/// - FLIPPER_PLUGIN_ABI: an integer bumped whenever the descriptor layout, any interface vtable,
///   the layout of a type passed across the boundary or the value of an enumerator that crosses
///   it changes, as LLVM does for pass plugins. It names the SDK's inline namespace
///   (`flipper::sdk::abi3`: a symbol built against another ABI does not link), and it is the
///   SOVERSION of libflipper_sdk (`libflipper_sdk.so.3`, sdk/CMakeLists.txt reads it here).
/// - The SDK semantic version: a plugin must have the same major, and its minor must be at most
///   the kernel's (a plugin built against a newer SDK minor may use what the kernel lacks).
/// - The build fingerprint: what else decides whether the two sides agree on the layout of what
///   they exchange (std::string, std::vector, std::shared_ptr): the C++ standard library and its
///   ABI, the pointer size, and the plugin ABI. It names no compiler: g++ and clang++ against the
///   same libstdc++ build plugins that load into each other's kernels. Boost.DLL does not check
///   any of this; a mismatch would crash instead of failing cleanly, so the loader compares it.
///
/// What changed in each version, and what a plugin author does about it: docs/sdk-migration.md.

#include <cstddef>  // a standard library header: defines _GLIBCXX_USE_CXX11_ABI / _LIBCPP_VERSION

#define FLIPPER_PLUGIN_ABI 3
#define FLIPPER_SDK_VERSION_MAJOR 3
#define FLIPPER_SDK_VERSION_MINOR 1
#define FLIPPER_SDK_VERSION_PATCH 0

#define FLIPPER_STRINGIFY_IMPL(x) #x
#define FLIPPER_STRINGIFY(x) FLIPPER_STRINGIFY_IMPL(x)
#define FLIPPER_CONCAT_IMPL(a, b) a##b
#define FLIPPER_CONCAT(a, b) FLIPPER_CONCAT_IMPL(a, b)

/// The SDK's inline namespace, `abi<FLIPPER_PLUGIN_ABI>`: every SDK declaration lives in
/// `flipper::sdk::FLIPPER_ABI_NAMESPACE` and is named `flipper::sdk::X` as usual.
#define FLIPPER_ABI_NAMESPACE FLIPPER_CONCAT(abi, FLIPPER_PLUGIN_ABI)

/// The C++ standard library and its ABI: libstdc++ with its dual string/list ABI flag, or libc++
/// with its ABI version.
#if defined(_LIBCPP_VERSION)
#define FLIPPER_STDLIB_ABI "libc++" FLIPPER_STRINGIFY(_LIBCPP_ABI_VERSION)
#elif defined(__GLIBCXX__)
#if defined(_GLIBCXX_USE_CXX11_ABI) && _GLIBCXX_USE_CXX11_ABI
#define FLIPPER_STDLIB_ABI "libstdc++;cxx11abi=1"
#else
#define FLIPPER_STDLIB_ABI "libstdc++;cxx11abi=0"
#endif
#else
#define FLIPPER_STDLIB_ABI "unknown-stdlib"
#endif

/// Build fingerprint compared by the loader; any difference refuses the plugin, e.g.
/// "abi=3;libstdc++;cxx11abi=1;ptrsize=8".
#define FLIPPER_BUILD_FINGERPRINT                                     \
  "abi=" FLIPPER_STRINGIFY(FLIPPER_PLUGIN_ABI) ";" FLIPPER_STDLIB_ABI \
                                               ";ptrsize=" FLIPPER_STRINGIFY(__SIZEOF_POINTER__)

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
struct SdkVersion {
  int major;
  int minor;
  int patch;
};
constexpr SdkVersion kSdkVersion{FLIPPER_SDK_VERSION_MAJOR, FLIPPER_SDK_VERSION_MINOR,
                                 FLIPPER_SDK_VERSION_PATCH};
/// The plugin ABI this SDK's namespace was generated for.
constexpr int kPluginAbi = FLIPPER_PLUGIN_ABI;
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
