#pragma once
/// @file config_keys.hpp
/// The studio's config keys, `serve.*` (docs/config.md "Who declares a key"; docs/studio.md):
/// declared here with the SDK's typed handles and nowhere else. config_schema() is the studio's
/// schema fragment, which the host composes with the kernel's before it loads a config;
/// ServeOptions takes its defaults from these handles and reads them (options.cpp). Header-only.

#include <cstdint>

#include "flipper/sdk/config_handles.hpp"

namespace flipper::studio::keys {

using Int = sdk::param::Int<std::int64_t>;
using Bool = sdk::param::Bool;
using Text = sdk::param::Text;
using Path = sdk::param::Path;
template <std::size_t N>
using TextList = sdk::param::TextList<N>;

inline constexpr Text kServeHost{"serve.host", "127.0.0.1", "address to listen on"};
inline constexpr Int kServePort{"serve.port", 8410, 0, 65535, "port (0: any free port, printed)"};
inline constexpr Int kServeThreads{"serve.threads", 4, 1, 256, "worker threads running requests"};
inline constexpr Int kServeMaxRequestBytes{"serve.max_request_bytes", 65536, 256, 67108864,
                                           "larger bodies: 413"};
inline constexpr Int kServeRatePerSecond{"serve.rate_per_second", 100, 1, 1000000,
                                         "requests per session per second"};
inline constexpr Int kServeRateBurst{"serve.rate_burst", 200, 1, 1000000, "burst per session"};
inline constexpr Int kServeMaxSessions{"serve.max_sessions", 1000, 1, 1000000, "open sessions"};
inline constexpr Int kServeSessionIdleS{"serve.session_idle_s", 3600, 1, 31536000,
                                        "idle seconds before a session may be evicted"};
inline constexpr Bool kServeSempre{"serve.sempre", false,
                                   "also answer the 2018 server's API at GET /sempre, to any web "
                                   "page (docs/sempre.md)"};
inline constexpr Bool kServeGuests{"serve.guests", true,
                                   "guests may use the server without an account"};
inline constexpr Int kServeLoginDays{"serve.login_days", 30, 1, 3650,
                                     "days a login (its cookie) lasts"};
inline constexpr Int kServeRequestTimeoutMs{"serve.request_timeout_ms", 10000, 100, 600000,
                                            "reading one request, headers and body"};
inline constexpr Int kServeIdleTimeoutMs{"serve.idle_timeout_ms", 5000, 100, 600000,
                                         "an idle keep-alive connection"};
inline constexpr Int kServeMaxConnections{"serve.max_connections", 1024, 1, 1000000,
                                          "open connections"};
inline constexpr Int kServeMaxConnectionsPerAddress{"serve.max_connections_per_address", 64, 1,
                                                    1000000, "open connections per client address"};
inline constexpr Int kServeSessionsPerAddress{"serve.sessions_per_address", 32, 1, 1000000,
                                              "open sessions per client address"};
inline constexpr Int kServeNewSessionsPerMinute{"serve.new_sessions_per_minute", 60, 1, 1000000,
                                                "new sessions per client address per minute"};
inline constexpr Int kServeMemoryBudgetMb{"serve.memory_budget_mb", 1024, 1, 1048576,
                                          "memory for all sessions' state (worlds)"};
inline constexpr Int kServeEvictAfterS{"serve.evict_after_s", 120, 0, 31536000,
                                       "idle seconds before the memory budget may evict"};
inline constexpr Int kServeCpuMsPerS{"serve.cpu_ms_per_s", 500, 1, 1000000,
                                     "CPU time per session per second"};
inline constexpr Int kServeCpuBurstMs{"serve.cpu_burst_ms", 5000, 1, 100000000,
                                      "CPU time a session may bank"};
inline constexpr Int kServeKernels{"serve.kernels", 0, 0, 64,
                                   "kernels answering at once (0: the cores + 1)"};

inline constexpr Path kServeWebDir{"serve.web_dir", "",
                                   "the page's files (empty: the installed ones)"};
inline constexpr Path kServeStudy{"serve.study", "", "a study description (empty: no study)"};
inline constexpr TextList<0> kServeSempreOrigins{
    "serve.sempre_origins",
    {},
    "web origins ('http://host:port') whose pages may use /sempre besides the server's own; '*' "
    "every origin (docs/sempre.md)"};
inline constexpr TextList<0> kServeAllowedHosts{
    "serve.allowed_hosts", {}, "more Host names the server answers to ('name' or 'name:port')"};
inline constexpr Path kServeAccounts{"serve.accounts", "",
                                     "the accounts store (empty: accounts.sqlite in the study's "
                                     "recording folder with serve.study, else beside "
                                     "lexicon.path)"};
inline constexpr Int kServeSessionsPerSubnet{
    "serve.sessions_per_subnet", 128, 1, 1000000,
    "open guest sessions per /24 (IPv4) or /64 (IPv6) subnet: 429 beyond"};
inline constexpr Int kServeNewGuestsPerMinute{
    "serve.new_guests_per_minute", 600, 1, 1000000,
    "new guest sessions per minute, all addresses together: 503 beyond"};
inline constexpr Int kServeReservedSessionsPercent{
    "serve.reserved_sessions_percent", 10, 0, 90,
    "per cent of serve.max_sessions that only logged-in users may open"};
inline constexpr Int kServeMaxConnectionsPerSubnet{
    "serve.max_connections_per_subnet", 256, 1, 1000000,
    "open connections per /24 (IPv4) or /64 (IPv6) subnet: 503 beyond"};
// HTTPS and proxies (docs/serve.md "HTTPS").
inline constexpr Path kServeTlsCert{"serve.tls.cert", "",
                                    "HTTPS: the certificate chain, PEM (empty: plain HTTP; needs "
                                    "serve.tls.key)"};
inline constexpr Path kServeTlsKey{"serve.tls.key", "",
                                   "HTTPS: the certificate's private key, PEM (unencrypted)"};
inline constexpr TextList<0> kServeBehindProxy{
    "serve.behind_proxy",
    {},
    "addresses of proxies whose X-Forwarded-For and X-Forwarded-Proto are trusted (from other "
    "peers both are ignored)"};

/// The studio's schema fragment: the section `serve`, in the order `flipper config explain`
/// lists it.
inline sdk::ParamSchema config_schema() {
  namespace param = sdk::param;
  sdk::ParamSchema s;
  s.add_section("serve", "flipper serve (Flipper Studio)");
  param::add(s, kServeHost);
  param::add(s, kServePort);
  param::add(s, kServeThreads);
  param::add(s, kServeMaxRequestBytes);
  param::add(s, kServeRatePerSecond);
  param::add(s, kServeRateBurst);
  param::add(s, kServeMaxSessions);
  param::add(s, kServeSessionIdleS);
  param::add(s, kServeWebDir);
  param::add(s, kServeStudy);
  // The schema's wording names the origins key; the handle's (above) is ServeOptions' comment.
  s.add_bool(std::string(kServeSempre.name), kServeSempre.def,
             "also answer the 2018 server's API at GET /sempre, to this page and "
             "serve.sempre_origins (docs/sempre.md)");
  param::add(s, kServeSempreOrigins);
  param::add(s, kServeAllowedHosts);
  param::add(s, kServeAccounts);
  param::add(s, kServeGuests);
  param::add(s, kServeLoginDays);
  param::add(s, kServeRequestTimeoutMs);
  param::add(s, kServeIdleTimeoutMs);
  param::add(s, kServeMaxConnections);
  param::add(s, kServeMaxConnectionsPerAddress);
  param::add(s, kServeSessionsPerAddress);
  param::add(s, kServeNewSessionsPerMinute);
  param::add(s, kServeMemoryBudgetMb);
  param::add(s, kServeEvictAfterS);
  param::add(s, kServeSessionsPerSubnet);
  param::add(s, kServeNewGuestsPerMinute);
  param::add(s, kServeReservedSessionsPercent);
  param::add(s, kServeMaxConnectionsPerSubnet);
  param::add(s, kServeCpuMsPerS);
  param::add(s, kServeCpuBurstMs);
  param::add(s, kServeKernels);
  param::add(s, kServeTlsCert);
  param::add(s, kServeTlsKey);
  param::add(s, kServeBehindProxy);
  return s;
}

}  // namespace flipper::studio::keys
