#pragma once
/// @file params.hpp
/// The typed parameter handles moved to the SDK (flipper/sdk/config_handles.hpp, one handle system
/// for plugin params and config keys); this name stays for plugins written against SDK 2.x
/// (docs/sdk-migration.md). New code includes the SDK header and writes `sdk::param`.

#include "flipper/sdk/config_handles.hpp"

namespace flipper::toolkit {
namespace param = sdk::param;
}  // namespace flipper::toolkit
