#pragma once
// Tests load configs as the product's host does: against the schema composed of the kernel's keys
// and each layer's (docs/config.md "Who declares a key"), installed once per test program before
// main() runs.
#include "flipper/wiring/config_schema.hpp"

namespace flipper::testsupport {
inline const bool kProductSchemaInstalled = (wiring::install_config_schema(), true);
}  // namespace flipper::testsupport
