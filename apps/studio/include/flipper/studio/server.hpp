#pragma once
/// @file server.hpp
/// `flipper serve`: one process, one kernel, many users. The session protocol over HTTP
/// (`POST /api/v1/request?session=TOKEN` takes one request object and answers exactly what
/// `flipper session` answers), logins (docs/accounts.md), the page's static files, and study
/// mode. docs/serve.md documents the HTTP mapping, docs/studio.md the transport,
/// limits and fairness.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/studio/config_keys.hpp"

namespace flipper::studio {

/// serve.* config keys; defaults from their declaration (flipper/studio/config_keys.hpp).
struct ServeOptions {
  std::string host{keys::kServeHost.def};
  int port = static_cast<int>(keys::kServePort.def);        ///< 0: any free port
  int threads = static_cast<int>(keys::kServeThreads.def);  ///< request workers
  std::size_t max_request_bytes = static_cast<std::size_t>(keys::kServeMaxRequestBytes.def);
  /// per session (token bucket)
  double rate_per_second = static_cast<double>(keys::kServeRatePerSecond.def);
  double rate_burst = static_cast<double>(keys::kServeRateBurst.def);
  std::size_t max_sessions = static_cast<std::size_t>(keys::kServeMaxSessions.def);
  int session_idle_s = static_cast<int>(keys::kServeSessionIdleS.def);
  std::string web_dir;                   ///< empty: found next to the binary or in the source tree
  std::string study;                     ///< a study description file (empty: no study mode)
  bool sempre = keys::kServeSempre.def;  ///< also answer GET /sempre (docs/sempre.md)
  /// Origins whose pages may use /sempre besides the server's own ("*": every origin).
  std::vector<std::string> sempre_origins;
  // Names and accounts (docs/accounts.md, docs/studio.md §3).
  std::vector<std::string> allowed_hosts;
  /// the accounts store (accounts_path()); with a study, set by the Server once it has loaded it
  std::string accounts;
  bool guests = keys::kServeGuests.def;
  int login_days = static_cast<int>(keys::kServeLoginDays.def);
  // Transport (docs/studio.md §2).
  int request_timeout_ms = static_cast<int>(keys::kServeRequestTimeoutMs.def);
  int idle_timeout_ms = static_cast<int>(keys::kServeIdleTimeoutMs.def);
  std::size_t max_connections = static_cast<std::size_t>(keys::kServeMaxConnections.def);
  std::size_t max_connections_per_address =
      static_cast<std::size_t>(keys::kServeMaxConnectionsPerAddress.def);
  // Sessions and memory (docs/studio.md §4).
  std::size_t sessions_per_address = static_cast<std::size_t>(keys::kServeSessionsPerAddress.def);
  int new_sessions_per_minute = static_cast<int>(keys::kServeNewSessionsPerMinute.def);
  std::size_t memory_budget_mb = static_cast<std::size_t>(keys::kServeMemoryBudgetMb.def);
  int evict_after_s = static_cast<int>(keys::kServeEvictAfterS.def);
  // Admission from many addresses (docs/studio.md §4 "Admission"; keys in kernel/config).
  std::size_t sessions_per_subnet = 128;       ///< guest sessions per /24 or /64
  int new_guests_per_minute = 600;             ///< new guest sessions, all addresses together
  std::size_t reserved_sessions_percent = 10;  ///< of max_sessions, for logged-in users
  std::size_t max_connections_per_subnet = 256;
  // Fairness (docs/studio.md §5).
  int cpu_ms_per_s = static_cast<int>(keys::kServeCpuMsPerS.def);
  int cpu_burst_ms = static_cast<int>(keys::kServeCpuBurstMs.def);
  /// Kernels per lexicon mode answering at once (serve.kernels; 0: the cores + 1), each
  /// charged to the memory budget (docs/studio.md §5).
  int kernels = static_cast<int>(keys::kServeKernels.def);
  // HTTPS and proxies (docs/serve.md "HTTPS", "Behind a proxy").
  std::string tls_cert;                   ///< PEM certificate chain (empty: plain HTTP)
  std::string tls_key;                    ///< its PEM private key
  std::vector<std::string> behind_proxy;  ///< proxies whose X-Forwarded-* are trusted
  static ServeOptions from_config(const kernel::Config& config);
};

/// Whether `host` names a loopback address (127.0.0.0/8, ::1, localhost).
bool is_loopback(const std::string& host);

/// The web directory: serve.web_dir when set, else the source tree's apps/studio/web (a build
/// tree), else <exe>/../share/flipper/web (an installed binary). Throws sdk::Error(bad_config).
std::string find_web_dir(const std::string& configured);

class Server {
 public:
  /// Builds the runtime's sessions factory (opens the lexicon), loads the page's files and the
  /// study. Throws sdk::Error (bad_config, bad_lexicon, plugin_*).
  explicit Server(const kernel::Config& config);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds serve.host:serve.port; returns the port bound. Throws sdk::Error(serve_failed).
  int bind();
  /// Serves until stop() (blocking; call bind() first).
  void listen();
  void stop();
  const ServeOptions& options() const;
  /// The connections served at once: serve.max_connections, lowered to fit the descriptor
  /// limit (raised to its hard limit at start; docs/studio.md §2).
  std::size_t connection_cap() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::studio
