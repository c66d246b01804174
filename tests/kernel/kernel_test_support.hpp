#pragma once
// Helpers shared by the kernel tests: where the test plugins are, temp config files, and an
// assertion on the exact error code and key words of a failure.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"
#include "product_schema.hpp"

namespace flipper::kerneltest {

inline std::string good_dir() {
  return std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/good";
}
inline std::string bad_dir() {
  return std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/bad";
}
inline std::string data_dir() {
  return std::string(FLIPPER_SOURCE_DIR) + "/tests/kernel/data";
}
inline std::string test_config_file() {
  return data_dir() + "/kernel_test.yaml";
}

/// The test config with the test plugin directories on the search path.
inline kernel::Config test_config(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), "plugin_paths=[" + good_dir() + ", " + bad_dir() + "]");
  return kernel::Config::load(test_config_file(), overrides);
}

/// Writes `text` to a fresh file under the build tree and returns its path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path.string();
}

/// Runs `f`, requires an sdk::Error with `code` whose message contains every word.
inline void require_error(const std::function<void()>& f, const std::string& code,
                          const std::vector<std::string>& words) {
  try {
    f();
  } catch (const sdk::Error& e) {
    INFO("message: " << e.what());
    CHECK(e.code() == code);
    for (const auto& w : words) {
      INFO("expected word: " << w);
      CHECK(std::string(e.what()).find(w) != std::string::npos);
    }
    return;
  }
  FAIL("expected an error with code " << code);
}

}  // namespace flipper::kerneltest
