#pragma once
/// @file session_factory.hpp
/// The one place where a front end gets a ready session: config, runtime, and every module's ops
/// and hooks installed (the naturalization module wires define/rules/delete_rule in here).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"

namespace flipper::kernel {

class Naturalizer;

/// Loads the config (file or embedded default, then overrides), builds the runtime and the
/// session. Throws sdk::Error (bad_config, plugin_*, bad_world, bad_grammar).
std::unique_ptr<Session> open_session(const std::optional<std::string>& config_file,
                                      const std::vector<std::string>& overrides);

/// A session over an existing runtime, with every module's ops installed.
std::unique_ptr<Session> open_session(std::shared_ptr<Runtime> runtime);

/// Many sessions over one runtime and one lexicon (a server's users): each session has its own
/// world, user and pending query; the lexicon store, the parser's grammar and the scorer are
/// shared, so the sharing mode applies across sessions exactly as between users of one session.
/// Not thread-safe: the caller serialises every call into the factory and its sessions.
class SessionFactory {
 public:
  /// Opens the lexicon (lexicon.*) once. Throws sdk::Error like open_session.
  explicit SessionFactory(std::shared_ptr<Runtime> runtime);
  ~SessionFactory();
  std::unique_ptr<Session> open() const;
  /// Call before handling a request of `session` when sessions interleave: with per-user
  /// weights (lexicon.weights: per_user) the scorer must hold this session's user's weights.
  void activate(const Session& session) const;
  Runtime& runtime() const { return *runtime_; }

 private:
  std::shared_ptr<Runtime> runtime_;
  std::shared_ptr<Naturalizer> naturalizer_;
};

}  // namespace flipper::kernel
