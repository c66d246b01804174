#pragma once
// Test support for session tests: a real runtime from the embedded default config (plugins from
// this build), with the lexicon in a scratch file so no test touches $HOME.
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "product_schema.hpp"

namespace flipper::testsupport {

// A fresh path under build/tests/scratch/run-XXXXXX, a directory made once per test process by
// mkdtemp. Not "<stem>-<pid>": pids wrap (pid_max 32768, and the crowd tests spawn hundreds of
// processes), and a later run's store then opened an earlier run's leftover .sqlite file.
inline std::string scratch_path(const std::string& stem) {
  static std::atomic<int> counter{0};
  static const std::filesystem::path dir = [] {
    const auto root = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "scratch";
    std::filesystem::create_directories(root);
    std::string pattern = (root / "run-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot make a scratch directory under " + root.string());
    return std::filesystem::path(pattern);
  }();
  return (dir / (stem + "-" + std::to_string(counter++))).string();
}

inline std::vector<std::string> test_overrides(std::vector<std::string> extra = {}) {
  extra.push_back("lexicon.path=" + scratch_path("lexicon") + ".sqlite");
  return extra;
}

inline std::shared_ptr<kernel::Runtime> test_runtime(std::vector<std::string> extra = {}) {
  return kernel::make_runtime(kernel::Config::load(std::nullopt, test_overrides(std::move(extra))));
}

/// A session with exactly the session module's own ops (no other module wired in).
inline std::unique_ptr<kernel::Session> bare_session(std::vector<std::string> extra = {}) {
  return std::make_unique<kernel::Session>(test_runtime(std::move(extra)));
}

/// Sends one request line, returns the parsed answer.
inline kernel::Json ask(kernel::Session& s, const std::string& line) {
  return kernel::Json::parse(s.handle_line(line));
}

inline std::string error_code(const kernel::Json& answer) {
  return answer.contains("error") ? answer["error"].value("code", std::string()) : std::string();
}

}  // namespace flipper::testsupport
