#pragma once
/// @file session_factory.hpp
/// The one place where a front end gets a ready session: config, runtime, and every extension's
/// ops and hooks installed (naturalization: define/rules/delete_rule). The app layer's wiring:
/// the kernel session knows no extension by name (flipper/kernel/session_extension.hpp).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_extension.hpp"

namespace flipper::naturalization {
class Naturalizer;
}

namespace flipper::wiring {

/// Loads the config (file or embedded default, then overrides), builds the runtime and the
/// session. Throws sdk::Error (bad_config, plugin_*, bad_world, bad_grammar).
std::unique_ptr<kernel::Session> open_session(const std::optional<std::string>& config_file,
                                              const std::vector<std::string>& overrides);

/// A session over an existing runtime, with every module's ops installed.
std::unique_ptr<kernel::Session> open_session(std::shared_ptr<kernel::Runtime> runtime);

/// One runtime and one lexicon (naturalizer) that several sessions share: the front ends that
/// serve many callers (`flipper serve`, the DDS node, the repl and session with DDS services) and
/// services that change the lexicon from outside a session (replication). Each session has its own
/// world, user and pending query; the lexicon store, the parser's grammar and the scorer are
/// shared, so the sharing mode applies across sessions exactly as between users of one session. Not
/// thread-safe: the owner serialises every call into the host and its sessions.
struct SessionHost {
  std::shared_ptr<kernel::Runtime> runtime;
  std::shared_ptr<naturalization::Naturalizer> naturalizer;
  /// What every session of this host gets attached, in order (naturalization first); a session
  /// moved to this host (Session::rebind) is given them too. Call Session::activate() before
  /// handling a request of a session when sessions interleave: with per-user weights
  /// (lexicon.weights: per_user) the scorer must hold this session's user's weights.
  kernel::Session::Extensions extensions;
  /// A new session over the shared runtime and lexicon, with every module's ops installed.
  std::unique_ptr<kernel::Session> open() const;
};
/// Opens the lexicon (lexicon.*) once over `runtime`. Throws sdk::Error like open_session.
SessionHost open_host(std::shared_ptr<kernel::Runtime> runtime);
SessionHost open_host(const std::optional<std::string>& config_file,
                      const std::vector<std::string>& overrides);

}  // namespace flipper::wiring
