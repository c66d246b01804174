#pragma once
/// @file export.hpp
/// Symbol visibility for the SDK. Everything is built with -fvisibility=hidden; every type that
/// crosses the kernel/plugin boundary (interfaces, exceptions) is marked FLIPPER_SDK_API so its
/// typeinfo and vtable live exactly once, in libflipper_sdk.so. Every SDK header includes this one,
/// and through it the ABI's inline namespace (version.hpp: FLIPPER_ABI_NAMESPACE).

#include "flipper/sdk/version.hpp"

#define FLIPPER_SDK_API __attribute__((visibility("default")))
#define FLIPPER_PLUGIN_EXPORT __attribute__((visibility("default")))
