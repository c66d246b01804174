#pragma once
// Who the client is when the server sits behind a proxy (docs/serve.md "Behind a proxy"): the
// peers listed in serve.behind_proxy are proxies, whose X-Forwarded-For names the client address
// and X-Forwarded-Proto the scheme the browser used; from any other peer both headers are
// ignored, so a client cannot pick the address its per-address limits are counted on, nor make
// the server believe it was reached over HTTPS.
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace flipper::studio {

/// The client as the server treats it: the address its limits count on, and whether its page
/// is HTTPS (cookies are then `Secure`, and its Origin is `https://`).
struct ClientView {
  std::string address;
  bool https = false;
};

class ProxyPolicy {
 public:
  ProxyPolicy() = default;
  /// `addresses`: IPv4 or IPv6 addresses. Throws sdk::Error(bad_config) naming an entry that
  /// is not one.
  explicit ProxyPolicy(const std::vector<std::string>& addresses);

  /// Whether `peer` (an address as the socket reports it) is a listed proxy.
  bool trusts(const std::string& peer) const;
  /// The client of a request from `peer` on a connection that is TLS or not. From a listed
  /// proxy: the rightmost X-Forwarded-For address that is not a listed proxy (the leftmost
  /// when all are; the peer without the header) and X-Forwarded-Proto's first value ("https");
  /// an X-Forwarded-For entry that is no address is nullopt with `error` set. From any other
  /// peer: the peer and the connection's own scheme.
  std::optional<ClientView> client(const std::string& peer, bool tls,
                                   const std::string& forwarded_for,
                                   const std::string& forwarded_proto, std::string& error) const;

 private:
  std::set<std::string> proxies_;  ///< canonical text of each address
};

/// An address in one spelling ("::ffff:10.0.0.1" -> "10.0.0.1", "0:0::1" -> "::1"); "" when
/// `text` is no IPv4 or IPv6 address.
std::string canonical_address(const std::string& text);

}  // namespace flipper::studio
