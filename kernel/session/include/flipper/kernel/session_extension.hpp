#pragma once
/// @file session_extension.hpp
/// The kernel's extension point for sessions (docs/architecture.md §3). A module above the kernel
/// (naturalization, a front end) adds its ops and hooks to a session through Session::set_op,
/// add_query_hook, add_user_hook, set_visibility and set_on_accept; Session::install keeps it, so
/// a front end finds its typed service with session.extension<T>(). The kernel names no
/// extension and reserves no op name for one: the app layer decides which extensions a session
/// gets (apps/wiring).

namespace flipper::kernel {

class Session;

class SessionExtension {
 public:
  virtual ~SessionExtension() = default;
  /// Installs the module's ops and hooks on a new session.
  virtual void install(Session& session) = 0;
  /// Called before a request of `session` is handled when several sessions share this extension
  /// (one host, interleaved callers): state the extension keeps per user must follow the caller.
  virtual void activate(const Session& session) { (void)session; }
};

}  // namespace flipper::kernel
