#pragma once
// A fresh, empty folder under build/tests/tmp/record for one test.
#include <filesystem>
#include <string>

namespace recordtest {
inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "record" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
}  // namespace recordtest
