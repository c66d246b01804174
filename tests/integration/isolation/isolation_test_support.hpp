#pragma once
// What the isolation tests share (docs/plugins-untrusted.md §6): where the misbehaving plugins
// are built, `--set` arguments, and answers compared without their timing.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flipper::isolationtest {

/// The folder of tests/support's evil plugins (evil_planner, evil_parser, evil_scorer).
inline const std::string kEvilDir = std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/evil";

/// " --set A --set B ..." for a command line.
inline std::string set_args(const std::vector<std::string>& sets) {
  std::string out;
  for (const auto& s : sets) out += " --set " + s;
  return out;
}

/// An answer without its `ms`, the one member that differs between equal answers.
inline nlohmann::json without_ms(nlohmann::json a) {
  a.erase("ms");
  return a;
}

}  // namespace flipper::isolationtest
