#pragma once
// Sessions over the real runtime (embedded default config, plugins of this build) with the
// naturalization ops wired in, and a lexicon in a scratch file.
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "session_fixture.hpp"

namespace flipper::naturalizetest {

using testsupport::error_code;
using testsupport::scratch_path;

/// A session whose lexicon lives at `store` (plus any extra --set overrides).
inline std::unique_ptr<kernel::Session> open(const std::string& store,
                                             std::vector<std::string> extra = {}) {
  extra.push_back("lexicon.path=" + store);
  return wiring::open_session(std::nullopt, extra);
}

inline kernel::Json ask(kernel::Session& s, const kernel::Json& request) {
  return s.handle(request);
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
  return a.value("status", std::string("error: ") + error_code(a));
}

/// The first candidate's formula of a query, "(none)" when it has none.
inline std::string first_formula(kernel::Session& s, const std::string& text) {
  const kernel::Json a = ask(s, {{"op", "query"}, {"text", text}});
  if (!a.value("ok", false) || a["candidates"].empty()) return "(none)";
  return a["candidates"][0].value("formula", std::string());
}

}  // namespace flipper::naturalizetest
