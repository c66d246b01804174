#pragma once
// Helpers of the toolkit config tests: files in the build tree, and the message of a refusal.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/document.hpp"

namespace configtest {

/// Writes `text` to `name` below build/tests/tmp/toolkit-config and returns its path.
inline std::string write_file(const std::string& name, const std::string& text) {
  const auto path =
      std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "toolkit-config" / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path.string();
}

/// The message of the bad_config error `f` throws (the code checked).
inline std::string config_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const flipper::sdk::Error& e) {
    CHECK(std::string(e.code()) == "bad_config");
    return e.what();
  }
  return "(no error: the document was accepted)";  // differs from every expected message
}

/// Rules of a small schema: `name` and `file` are text keys, `planner` a plugin section.
inline flipper::toolkit::config::DocumentRules rules() {
  return {[](const std::string& key) { return key == "name" || key == "grammar.file"; },
          {"world", "planner"},
          "/defaults"};
}

}  // namespace configtest
