#pragma once
// The studio's HTTP/1.1 server on Boost.Beast/Asio (docs/studio.md §2): one I/O thread serves
// every connection asynchronously, so an idle or slow client holds a socket, never a thread.
// Reading a request (headers and body) has one total deadline; an idle keep-alive connection is
// closed after its own limit; connections are capped per client address and in total; framing is
// strict (conflicting or invalid Content-Length: 400, a Transfer-Encoding other than chunked:
// 501), and pipelined requests are answered one after another, in order. Routes answer through
// a callback, so the work behind one can run on another thread (scheduler.hpp). With
// serve.tls.* every connection is TLS (Beast's ssl_stream over OpenSSL); a plain HTTP request
// to it is answered 400 `https_required` and closed (docs/serve.md "HTTPS").
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "http_types.hpp"

namespace flipper::studio {

struct TransportOptions {
  int request_timeout_ms = 10000;  ///< from a request's first byte to its last (headers + body)
  int idle_timeout_ms = 5000;      ///< a keep-alive connection waiting for its next request
  int write_timeout_ms = 10000;    ///< writing one answer
  std::size_t max_connections = 1024;
  std::size_t max_connections_per_address = 64;
  std::size_t max_connections_per_subnet = 256;  ///< per /24 (IPv4) or /64 (IPv6)
  std::size_t max_request_bytes = 65536;         ///< the body
  std::size_t max_header_bytes = 16384;          ///< request line and headers
  /// HTTPS (docs/serve.md "HTTPS"): the certificate chain and its key, PEM; both empty: HTTP.
  std::string tls_cert;
  std::string tls_key;
  /// Proxies whose X-Forwarded-For/-Proto are trusted (proxy_policy.hpp); their own
  /// connections are not capped per address or subnet (they carry many clients).
  std::vector<std::string> behind_proxy;
};

/// Method + path -> route; then method + path prefix -> route (the longest prefix wins); other
/// paths of a method go to its fallback (the page's files). A path that a route or prefix takes
/// with another method is 405.
class Router {
 public:
  void add(const std::string& method, const std::string& path, Route route);
  /// Every path that starts with `prefix` (which ends with '/'), e.g. one file of a folder.
  void add_prefix(const std::string& method, const std::string& prefix, Route route);
  void fallback(const std::string& method, Route route);
  /// Runs before any route; a reply it returns is sent instead (host checks).
  void guard(std::function<bool(const HttpRequest&, HttpReply&)> refuse) {
    guard_ = std::move(refuse);
  }
  void dispatch(const HttpRequest& request, Respond respond) const;

 private:
  std::map<std::pair<std::string, std::string>, Route> routes_;
  std::map<std::pair<std::string, std::string>, Route> prefixes_;
  std::map<std::string, Route> fallbacks_;
  std::function<bool(const HttpRequest&, HttpReply&)> guard_;
};

class HttpTransport {
 public:
  /// Throws sdk::Error(bad_config) for bad TLS files or proxy addresses.
  HttpTransport(TransportOptions options, const Router& router);
  ~HttpTransport();
  HttpTransport(const HttpTransport&) = delete;
  HttpTransport& operator=(const HttpTransport&) = delete;

  /// Listens on host:port (0: any free port); returns the port. Throws sdk::Error(serve_failed).
  int bind(const std::string& host, int port);
  /// Serves until stop() (blocking).
  void run();
  /// Safe from any thread.
  void stop();

  struct Impl;  ///< (the connections use it)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace flipper::studio
