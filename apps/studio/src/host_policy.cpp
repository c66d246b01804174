// Host and Origin checks (host_policy.hpp, docs/studio.md §3).
#include "host_policy.hpp"

#include <algorithm>
#include <cctype>

namespace flipper::studio {
namespace {

std::string lower_host(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// "name" -> "name:port"; "name:port" and "[v6]:port" stay; "[v6]" gets the port; a bare IPv6
// address is bracketed.
std::string with_port(const std::string& host, int port) {
  const std::string p = std::to_string(port);
  if (host.empty()) return host;
  if (host.front() == '[') return host.find("]:") != std::string::npos ? host : host + ":" + p;
  const auto colons = std::count(host.begin(), host.end(), ':');
  if (colons == 0) return host + ":" + p;
  if (colons == 1) return host;
  return "[" + host + "]:" + p;  // a bare IPv6 address
}

}  // namespace

HostPolicy::HostPolicy(const std::string& bound_host, int port,
                       const std::vector<std::string>& allowed)
    : port_(port) {
  // A wildcard address is no name a client sends: such servers list their names.
  if (bound_host != "0.0.0.0" && bound_host != "::" && bound_host != "[::]")
    hosts_.insert(lower_host(with_port(bound_host, port)));
  hosts_.insert("localhost:" + std::to_string(port));
  for (const auto& name : allowed) hosts_.insert(lower_host(with_port(name, port)));
}

bool HostPolicy::allows_host(const std::string& host, bool https) const {
  if (host.empty()) return false;
  // No port in the header: the scheme's default.
  return hosts_.count(lower_host(with_port(host, https ? 443 : 80))) > 0;
}

bool HostPolicy::allows_origin(const HttpRequest& r) const {
  // Fetch metadata first: a browser marks cross-site requests itself.
  if (!r.sec_fetch_site.empty() && r.sec_fetch_site != "same-origin" && r.sec_fetch_site != "none")
    return false;
  if (r.origin.empty()) return true;  // not a browser (curl, programs, the benchmark)
  // An HTTPS page's origin is https:// (docs/serve.md "HTTPS"), a plain page's http://.
  const std::string scheme = r.secure ? "https://" : "http://";
  if (lower_host(r.origin.substr(0, scheme.size())) != scheme) return false;
  const std::string host = r.origin.substr(scheme.size());
  if (host.find('/') != std::string::npos) return false;
  return allows_host(host, r.secure);
}

bool HostPolicy::refuse(const HttpRequest& r, HttpReply& reply) const {
  if (allows_host(r.host, r.secure)) return false;
  reply = error_reply(421, "wrong_host",
                      "this server does not answer to Host '" + r.host.substr(0, 200) +
                          "' (it answers to its own address, localhost and serve.allowed_hosts)");
  return true;
}

}  // namespace flipper::studio
