#pragma once
// What the isolation tests share (docs/plugins-untrusted.md §6): where the misbehaving plugins
// are built, `--set` arguments, and answers compared without their timing.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sanitizer_build.hpp"

namespace flipper::isolationtest {

/// The folder of tests/support's evil plugins (evil_planner, evil_parser, evil_scorer).
inline const std::string kEvilDir = std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/evil";

/// " --set A --set B ..." for a command line.
inline std::string set_args(const std::vector<std::string>& sets) {
  std::string out;
  for (const auto& s : sets) out += " --set " + s;
  return out;
}

/// A server's `--set` values with isolation as the server has it by default: `auto` (process in
/// a server) in Release; said explicitly in the AddressSanitizer tree, whose servers keep `auto`
/// in process (docs/plugins-untrusted.md §6, "Where it is on").
inline std::vector<std::string> isolated_server(std::vector<std::string> sets) {
  if (testsupport::kAddressSanitizer) sets.emplace_back("plugins.isolation=process");
  return sets;
}

/// An answer without its `ms`, the one member that differs between equal answers.
inline nlohmann::json without_ms(nlohmann::json a) {
  a.erase("ms");
  return a;
}

}  // namespace flipper::isolationtest
