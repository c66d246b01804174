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

/// One runtime and one lexicon (naturalizer) that several sessions share: front ends serving
/// many callers (the DDS node) and services that change the lexicon from outside a session
/// (replication) use it. Not thread-safe: the owner serialises calls.
struct SessionHost {
  std::shared_ptr<Runtime> runtime;
  std::shared_ptr<Naturalizer> naturalizer;
  /// A new session over the shared runtime and lexicon, with every module's ops installed.
  std::unique_ptr<Session> open() const;
};
SessionHost open_host(const std::optional<std::string>& config_file,
                      const std::vector<std::string>& overrides);

}  // namespace flipper::kernel
