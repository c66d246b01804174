#pragma once
// The names this server answers to (docs/studio.md §3): the bound address with its port,
// `localhost` with it, and the names in serve.allowed_hosts ("name" with the bound port, or
// "name:port"). A request with another Host is refused (421), whatever its Origin: a page on a
// rebound name (evil.example resolving to 127.0.0.1) cannot reach the API. A POST whose Origin
// is not `http://` (`https://` when the page is HTTPS) + one of these names, or that the browser
// marks cross-site, is refused (403).
#include <set>
#include <string>
#include <vector>

#include "http_types.hpp"

namespace flipper::studio {

class HostPolicy {
 public:
  HostPolicy() = default;
  HostPolicy(const std::string& bound_host, int port, const std::vector<std::string>& allowed);

  /// Whether a Host header ("name", "name:port", "[v6]:port") names this server; without a
  /// port it means the scheme's default (443 for `https`, else 80).
  bool allows_host(const std::string& host, bool https = false) const;
  /// Whether a state-changing request comes from this server's own pages (or from no browser).
  bool allows_origin(const HttpRequest& request) const;
  /// The Host check as a router guard: true (and `reply` set) when refused.
  bool refuse(const HttpRequest& request, HttpReply& reply) const;

 private:
  std::set<std::string> hosts_;  ///< lower-case "name:port"
  int port_ = 0;
};

}  // namespace flipper::studio
