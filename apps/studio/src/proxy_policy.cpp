// Trusted proxies and the forwarded headers (proxy_policy.hpp, docs/serve.md "Behind a proxy").
#include "proxy_policy.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <cstring>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
namespace {

std::string trim(std::string s) {
  const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), space));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), space).base(), s.end());
  return s;
}

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t at = 0;
  while (at <= text.size()) {
    const auto comma = text.find(',', at);
    const std::string part =
        trim(text.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
    if (!part.empty()) parts.push_back(part);
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return parts;
}

// "1.2.3.4:80" -> "1.2.3.4", "[::1]:80" and "[::1]" -> "::1" (proxies that add the port).
std::string without_port(const std::string& text) {
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    return close == std::string::npos ? text : text.substr(1, close - 1);
  }
  if (std::count(text.begin(), text.end(), ':') == 1) return text.substr(0, text.find(':'));
  return text;
}

}  // namespace

std::string canonical_address(const std::string& text) {
  char out[INET6_ADDRSTRLEN] = {};
  in_addr v4{};
  if (::inet_pton(AF_INET, text.c_str(), &v4) == 1)
    return ::inet_ntop(AF_INET, &v4, out, sizeof out) != nullptr ? out : "";
  in6_addr v6{};
  if (::inet_pton(AF_INET6, text.c_str(), &v6) != 1) return "";
  if (IN6_IS_ADDR_V4MAPPED(&v6)) {
    std::memcpy(&v4, &v6.s6_addr[12], sizeof v4);
    return ::inet_ntop(AF_INET, &v4, out, sizeof out) != nullptr ? out : "";
  }
  return ::inet_ntop(AF_INET6, &v6, out, sizeof out) != nullptr ? out : "";
}

ProxyPolicy::ProxyPolicy(const std::vector<std::string>& addresses) {
  for (const auto& entry : addresses) {
    const std::string address = canonical_address(trim(entry));
    if (address.empty())
      throw sdk::Error(sdk::codes::kBadConfig,
                       "serve.behind_proxy: '" + entry +
                           "' is not an IPv4 or IPv6 address (list each proxy's address)");
    proxies_.insert(address);
  }
}

bool ProxyPolicy::trusts(const std::string& peer) const {
  return !proxies_.empty() && proxies_.count(canonical_address(peer)) > 0;
}

std::optional<ClientView> ProxyPolicy::client(const std::string& peer, bool tls,
                                              const std::string& forwarded_for,
                                              const std::string& forwarded_proto,
                                              std::string& error) const {
  if (!trusts(peer)) return ClientView{peer, tls};
  ClientView view{peer, tls};
  const auto protos = split_commas(forwarded_proto);
  if (!protos.empty()) {
    std::string first = protos.front();
    std::transform(first.begin(), first.end(), first.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    view.https = first == "https";
  }
  const auto hops = split_commas(forwarded_for);
  // Each proxy appends the address it was reached from: walk back over the listed proxies.
  for (auto hop = hops.rbegin(); hop != hops.rend(); ++hop) {
    const std::string address = canonical_address(without_port(*hop));
    if (address.empty()) {
      error = "X-Forwarded-For names '" + hop->substr(0, 100) + "', which is not an address";
      return std::nullopt;
    }
    view.address = address;
    if (proxies_.count(address) == 0) break;
  }
  return view;
}

}  // namespace flipper::studio
