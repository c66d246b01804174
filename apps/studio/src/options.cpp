// serve.* keys (read through config_keys.hpp), loopback detection and where the page's files are.
#include <arpa/inet.h>

#include <filesystem>
#include <system_error>

#include "flipper/sdk/errors.hpp"
#include "flipper/studio/accounts.hpp"
#include "flipper/studio/config_keys.hpp"
#include "flipper/studio/server.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;

ServeOptions ServeOptions::from_config(const kernel::Config& c) {
  ServeOptions o;
  o.host = c.get(keys::kServeHost);
  o.port = static_cast<int>(c.get(keys::kServePort));
  o.threads = static_cast<int>(c.get(keys::kServeThreads));
  o.max_request_bytes = static_cast<std::size_t>(c.get(keys::kServeMaxRequestBytes));
  o.rate_per_second = static_cast<double>(c.get(keys::kServeRatePerSecond));
  o.rate_burst = static_cast<double>(c.get(keys::kServeRateBurst));
  o.max_sessions = static_cast<std::size_t>(c.get(keys::kServeMaxSessions));
  o.session_idle_s = static_cast<int>(c.get(keys::kServeSessionIdleS));
  o.allowed_hosts = c.get(keys::kServeAllowedHosts);
  // With a study the server resolves it from the loaded study's folder (Server::Server): the
  // study file is read once.
  if (c.text(keys::kServeStudy).empty()) o.accounts = accounts_path(c);
  o.guests = c.get(keys::kServeGuests);
  o.login_days = static_cast<int>(c.get(keys::kServeLoginDays));
  o.request_timeout_ms = static_cast<int>(c.get(keys::kServeRequestTimeoutMs));
  o.idle_timeout_ms = static_cast<int>(c.get(keys::kServeIdleTimeoutMs));
  o.max_connections = static_cast<std::size_t>(c.get(keys::kServeMaxConnections));
  o.max_connections_per_address =
      static_cast<std::size_t>(c.get(keys::kServeMaxConnectionsPerAddress));
  o.sessions_per_address = static_cast<std::size_t>(c.get(keys::kServeSessionsPerAddress));
  o.new_sessions_per_minute = static_cast<int>(c.get(keys::kServeNewSessionsPerMinute));
  o.memory_budget_mb = static_cast<std::size_t>(c.get(keys::kServeMemoryBudgetMb));
  o.evict_after_s = static_cast<int>(c.get(keys::kServeEvictAfterS));
  o.sessions_per_subnet = static_cast<std::size_t>(c.get(keys::kServeSessionsPerSubnet));
  o.new_guests_per_minute = static_cast<int>(c.get(keys::kServeNewGuestsPerMinute));
  o.reserved_sessions_percent =
      static_cast<std::size_t>(c.get(keys::kServeReservedSessionsPercent));
  o.max_connections_per_subnet =
      static_cast<std::size_t>(c.get(keys::kServeMaxConnectionsPerSubnet));
  o.cpu_ms_per_s = static_cast<int>(c.get(keys::kServeCpuMsPerS));
  o.cpu_burst_ms = static_cast<int>(c.get(keys::kServeCpuBurstMs));
  o.kernels = static_cast<int>(c.get(keys::kServeKernels));
  if (!c.text(keys::kServeWebDir).empty()) o.web_dir = c.get(keys::kServeWebDir);
  if (!c.text(keys::kServeStudy).empty()) o.study = c.get(keys::kServeStudy);
  o.sempre = c.get(keys::kServeSempre);
  o.sempre_origins = c.get(keys::kServeSempreOrigins);
  if (!c.text(keys::kServeTlsCert).empty()) o.tls_cert = c.get(keys::kServeTlsCert);
  if (!c.text(keys::kServeTlsKey).empty()) o.tls_key = c.get(keys::kServeTlsKey);
  o.behind_proxy = c.get(keys::kServeBehindProxy);
  return o;
}

bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (inet_pton(AF_INET6, host.c_str(), &v6) == 1) return IN6_IS_ADDR_LOOPBACK(&v6);
  return false;
}

std::string find_web_dir(const std::string& configured) {
  std::error_code ec;
  if (!configured.empty()) {
    if (!fs::is_regular_file(fs::path(configured) / "index.html", ec))
      throw sdk::Error(sdk::codes::kBadConfig,
                       "serve.web_dir '" + configured + "' has no index.html");
    return configured;
  }
  // Relative to the executable only: the install layout, which the build tree mirrors with a
  // link to apps/studio/web (no source path compiled in).
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / FLIPPER_STUDIO_INSTALLED_WEB_DIR;
    const fs::path real = fs::canonical(installed, ec);
    if (!ec && fs::is_regular_file(real / "index.html", ec)) return real.string();
  }
  throw sdk::Error(sdk::codes::kBadConfig, "cannot find the page's files (looked in <exe>/../" +
                                               std::string(FLIPPER_STUDIO_INSTALLED_WEB_DIR) +
                                               "); set serve.web_dir");
}

}  // namespace flipper::studio
