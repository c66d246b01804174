#pragma once
// Sessions over the real runtime (embedded default config, plugins of this build) with the
// naturalization ops wired in, and a lexicon in a scratch file.
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_factory.hpp"

namespace flipper::naturalizetest {

inline std::string scratch(const std::string& stem) {
  static std::atomic<int> counter{0};
  auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "scratch";
  std::filesystem::create_directories(dir);
  auto p = dir / (stem + "-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove(p);
  return p.string();
}

/// A session whose lexicon lives at `store` (plus any extra --set overrides).
inline std::unique_ptr<kernel::Session> open(const std::string& store,
                                             std::vector<std::string> extra = {}) {
  extra.push_back("lexicon.path=" + store);
  return kernel::open_session(std::nullopt, extra);
}

inline kernel::Json ask(kernel::Session& s, const kernel::Json& request) {
  return s.handle(request);
}

inline std::string code(const kernel::Json& answer) {
  return answer.contains("error") ? answer["error"].value("code", std::string()) : std::string();
}

inline kernel::Json user(kernel::Session& s, const std::string& name) {
  return s.handle({{"op", "user"}, {"name", name}});
}

inline kernel::Json define(kernel::Session& s, const std::string& head,
                           std::vector<std::string> body) {
  return s.handle({{"op", "define"}, {"head", head}, {"body", body}});
}

inline std::string status(kernel::Session& s, const std::string& text) {
  auto a = s.handle({{"op", "query"}, {"text", text}});
  return a.value("status", std::string("error: ") + code(a));
}

}  // namespace flipper::naturalizetest
