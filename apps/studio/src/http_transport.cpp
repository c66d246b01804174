// Boost.Beast/Asio HTTP/1.1 server of the studio (http_transport.hpp, docs/studio.md §2).
#include "http_transport.hpp"

#include <openssl/err.h>
#include <openssl/ssl.h>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <type_traits>

#include "flipper/sdk/errors.hpp"
#include "proxy_policy.hpp"
#include "registry.hpp"
#include "tls_context.hpp"

namespace flipper::studio {
namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
namespace ssl = boost::asio::ssl;
using tcp = net::ip::tcp;

const std::vector<std::pair<std::string, std::string>>& security_headers() {
  // An answer is never framed by another site, never sniffed as another type, never leaks the
  // address it came from; an API answer loads nothing (docs/studio.md §2 "Headers"). The page's
  // files set their own Content-Security-Policy (static_reply), also with frame-ancestors 'none'.
  static const std::vector<std::pair<std::string, std::string>> kHeaders = {
      {"X-Content-Type-Options", "nosniff"},
      {"X-Frame-Options", "DENY"},
      {"Referrer-Policy", "no-referrer"},
      {"Content-Security-Policy", "default-src 'none'; frame-ancestors 'none'"}};
  return kHeaders;
}

std::string error_body(const std::string& code, const std::string& message) {
  nlohmann::json a;
  a["ok"] = false;
  a["op"] = nullptr;
  a["error"] = nlohmann::json{{"code", code}, {"message", without_paths(message)}};
  return a.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

HttpReply error_reply(int status, const std::string& code, const std::string& message) {
  HttpReply r;
  r.status = status;
  r.body = error_body(code, message);
  return r;
}

HttpReply json_reply(int status, const nlohmann::json& body) {
  HttpReply r;
  r.status = status;
  r.body = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  r.set_header("Cache-Control", "no-store");
  return r;
}

void Router::add(const std::string& method, const std::string& path, Route route) {
  routes_[{method, path}] = std::move(route);
}

void Router::add_prefix(const std::string& method, const std::string& prefix, Route route) {
  prefixes_[{method, prefix}] = std::move(route);
}

void Router::fallback(const std::string& method, Route route) {
  fallbacks_[method] = std::move(route);
}

void Router::dispatch(const HttpRequest& request, Respond respond) const {
  HttpReply refused;
  if (guard_ && guard_(request, refused)) return respond(std::move(refused));
  if (auto it = routes_.find({request.method, request.path}); it != routes_.end())
    return it->second(request, std::move(respond));
  for (const auto& [key, route] : routes_)
    if (key.second == request.path)
      return respond(error_reply(405, "method_not_allowed", "this path does not take that method"));
  const Route* longest = nullptr;
  std::size_t longest_size = 0;
  bool other_method = false;
  for (const auto& [key, route] : prefixes_) {
    if (!request.path.starts_with(key.second) || key.second.size() < longest_size) continue;
    if (key.first != request.method) {
      other_method = true;
      continue;
    }
    longest = &route;
    longest_size = key.second.size();
  }
  if (longest != nullptr) return (*longest)(request, std::move(respond));
  if (other_method)
    return respond(error_reply(405, "method_not_allowed", "this path does not take that method"));
  if (auto it = fallbacks_.find(request.method); it != fallbacks_.end())
    return it->second(request, std::move(respond));
  respond(error_reply(404, "not_found", "no such page or API path"));
}

namespace {

std::string_view sv(beast::string_view s) {
  return {s.data(), s.size()};
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percent_decode(std::string_view s, bool plus_is_space) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      const int hi = hex_value(s[i + 1]), lo = hex_value(s[i + 2]);
      if (hi >= 0 && lo >= 0) {
        out.push_back(static_cast<char>(hi * 16 + lo));
        i += 2;
        continue;
      }
    }
    out.push_back(plus_is_space && s[i] == '+' ? ' ' : s[i]);
  }
  return out;
}

void split_target(std::string_view target, HttpRequest& r) {
  const auto q = target.find('?');
  r.path = percent_decode(target.substr(0, q), false);
  if (q == std::string_view::npos) return;
  r.raw_query = std::string(target.substr(q + 1));
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    const auto eq = pair.find('=');
    std::string key = percent_decode(pair.substr(0, eq), true);
    std::string value =
        eq == std::string_view::npos ? "" : percent_decode(pair.substr(eq + 1), true);
    r.query.emplace(std::move(key), std::move(value));
    if (amp == std::string_view::npos) break;
    rest.remove_prefix(amp + 1);
  }
}

// A whole refusal (503 too_many_connections, or 400 https_required), written to a socket
// that is closed after it.
std::string refusal_text(const std::string& message,
                         const std::string& status_line = "503 Service Unavailable",
                         const std::string& code = "too_many_connections") {
  const std::string body = error_body(code, message);
  std::string text = "HTTP/1.1 " + status_line +
                     "\r\nContent-Type: "
                     "application/json\r\nConnection: close\r\nContent-Length: " +
                     std::to_string(body.size()) + "\r\n";
  for (const auto& [k, v] : security_headers()) text += k + ": " + v + "\r\n";
  return text + "\r\n" + body;
}

bool is_chunked_only(std::string_view te) {
  while (!te.empty() && std::isspace(static_cast<unsigned char>(te.front()))) te.remove_prefix(1);
  while (!te.empty() && std::isspace(static_cast<unsigned char>(te.back()))) te.remove_suffix(1);
  if (te.size() != 7) return false;
  for (std::size_t i = 0; i < 7; ++i)
    if (std::tolower(static_cast<unsigned char>(te[i])) != "chunked"[i]) return false;
  return true;
}

// Set-Cookie values without a Secure attribute get one (an HTTPS page's cookies never travel
// over plain HTTP; docs/serve.md "HTTPS").
void make_cookies_secure(http::response<http::string_body>& res) {
  std::vector<std::string> cookies;
  for (const auto& field : res) {
    if (field.name() != http::field::set_cookie) continue;
    std::string value(sv(field.value()));
    std::string lower = value;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower.find("; secure") == std::string::npos) value += "; Secure";
    cookies.push_back(std::move(value));
  }
  if (cookies.empty()) return;
  res.erase(http::field::set_cookie);
  for (auto& cookie : cookies) res.insert(http::field::set_cookie, cookie);
}

// Every value of a header that may be repeated, joined by commas (RFC 9110 §5.3).
std::string joined(const http::request<http::string_body>& req, beast::string_view name) {
  std::string all;
  for (auto [it, end] = req.equal_range(name); it != end; ++it) {
    if (!all.empty()) all += ", ";
    all += sv(it->value());
  }
  return all;
}

}  // namespace

struct HttpTransport::Impl {
  Impl(TransportOptions o, const Router& r)
      : options(std::move(o)), router(r), proxies(options.behind_proxy) {
    if (!options.tls_cert.empty() || !options.tls_key.empty())
      tls = make_tls_context(options.tls_cert, options.tls_key);
  }
  TransportOptions options;
  const Router& router;
  ProxyPolicy proxies;
  std::unique_ptr<ssl::context> tls;  ///< null: plain HTTP
  // Before io: destroying io destroys the connections still pending, which release here.
  std::mutex mutex;  // the connection counts (a connection may end on a worker thread)
  std::map<std::string, std::size_t> per_address;
  std::map<std::string, std::size_t> per_subnet;
  std::size_t total = 0;
  net::io_context io{1};
  tcp::acceptor acceptor{io};
  net::steady_timer backoff{io};
  /// A descriptor kept free: at EMFILE it is closed to accept one waiting connection, refuse it
  /// and close it, then taken again (docs/studio.md §2 "Descriptors").
  int spare_fd = -1;
  /// The refusal sent at EMFILE, written once here: a process out of descriptors builds nothing.
  const std::string out_of_descriptors_text = refusal_text(
      "the server has no descriptors left for connections (its descriptor limit); try later");

  ~Impl() {
    if (spare_fd >= 0) ::close(spare_fd);
  }
  void accept();
  void admit(tcp::socket socket);
  /// Out of descriptors: refuses the oldest waiting connection, then waits before accepting
  /// again (instead of retrying at once, which spins: the connection stays in the backlog).
  void out_of_descriptors();
  void release(const std::string& peer) {
    std::lock_guard lock(mutex);
    --total;
    if (--per_address[peer] == 0) per_address.erase(peer);
    if (--per_subnet[subnet_of(peer)] == 0) per_subnet.erase(subnet_of(peer));
  }
};

namespace {

// One connection over a plain TCP stream or TLS over it (Stream: beast::tcp_stream or
// beast::ssl_stream<beast::tcp_stream>).
template <class Stream>
class Connection : public std::enable_shared_from_this<Connection<Stream>> {
  static constexpr bool kTls = !std::is_same_v<Stream, beast::tcp_stream>;

 public:
  Connection(HttpTransport::Impl* server, Stream stream, std::string peer)
      : server_(server), stream_(std::move(stream)), peer_(std::move(peer)) {}
  ~Connection() { server_->release(peer_); }

  void start() {
    if constexpr (!kTls) {
      wait_for_request();
    } else {
      // The handshake falls under the request deadline: a client that never finishes it
      // holds a socket for serve.request_timeout_ms at most.
      lowest().expires_after(std::chrono::milliseconds(options().request_timeout_ms));
      stream_.async_handshake(ssl::stream_base::server,
                              [self = this->shared_from_this()](beast::error_code ec) {
                                if (ec) return self->handshake_failed(ec);
                                self->wait_for_request();
                              });
    }
  }

 private:
  const TransportOptions& options() const { return server_->options; }
  beast::tcp_stream& lowest() { return beast::get_lowest_layer(stream_); }

  // Plain HTTP sent to the HTTPS port is told so in plain HTTP (OpenSSL recognises the
  // request line); any other failed handshake is closed without a word.
  void handshake_failed(beast::error_code ec) {
    if (ec.category() == net::error::get_ssl_category() &&
        ERR_GET_REASON(static_cast<unsigned long>(ec.value())) == SSL_R_HTTP_REQUEST) {
      const std::string text = refusal_text("this port speaks HTTPS: use https:// (serve.tls.cert)",
                                            "400 Bad Request", "https_required");
      beast::error_code ignored;
      lowest().socket().non_blocking(true, ignored);
      lowest().socket().write_some(net::buffer(text), ignored);
    }
    beast::error_code ignored;
    lowest().socket().shutdown(tcp::socket::shutdown_both, ignored);
    lowest().close();
  }

  // Idle until the next request's first byte (or pipelined bytes are already buffered).
  void wait_for_request() {
    if (buffer_.size() > 0) return read_request();
    lowest().expires_after(std::chrono::milliseconds(options().idle_timeout_ms));
    stream_.async_read_some(buffer_.prepare(4096),
                            [self = this->shared_from_this()](beast::error_code ec, std::size_t n) {
                              if (ec) return self->close();
                              self->buffer_.commit(n);
                              self->read_request();
                            });
  }

  // One deadline for the whole request: headers, then the body.
  void read_request() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(options().max_header_bytes));
    parser_->body_limit(options().max_request_bytes);
    lowest().expires_after(std::chrono::milliseconds(options().request_timeout_ms));
    http::async_read_header(stream_, buffer_, *parser_,
                            [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                              self->on_header(ec);
                            });
  }

  void on_header(beast::error_code ec) {
    if (ec) return fail(ec);
    const auto& req = parser_->get();
    const auto te = req[http::field::transfer_encoding];
    if (!te.empty() && !is_chunked_only(sv(te)))
      return refuse(501, "unsupported_transfer_encoding",
                    "Transfer-Encoding '" + std::string(sv(te)) +
                        "' is not supported (only chunked, or a Content-Length)");
    if (!te.empty() && req.count(http::field::content_length) > 0)
      return refuse(400, "bad_framing",
                    "a request may not carry both Transfer-Encoding and "
                    "Content-Length");
    http::async_read(
        stream_, buffer_, *parser_,
        [self = this->shared_from_this()](beast::error_code e, std::size_t) { self->on_body(e); });
  }

  void on_body(beast::error_code ec) {
    if (ec) return fail(ec);
    auto req = parser_->release();
    parser_.reset();
    HttpRequest r;
    r.method = std::string(sv(req.method_string()));
    split_target(sv(req.target()), r);
    r.host = std::string(sv(req[http::field::host]));
    r.origin = std::string(sv(req[http::field::origin]));
    r.sec_fetch_site = std::string(sv(req["Sec-Fetch-Site"]));
    r.cookie = std::string(sv(req[http::field::cookie]));
    r.body = std::move(req.body());
    close_after_ = !req.keep_alive();
    std::string bad_forwarding;
    const auto client = server_->proxies.client(peer_, kTls, joined(req, "X-Forwarded-For"),
                                                joined(req, "X-Forwarded-Proto"), bad_forwarding);
    if (!client) return refuse(400, "bad_forwarded_for", bad_forwarding);
    r.peer = client->address;
    r.secure = client->https;
    secure_ = client->https;
    // The route's own limits bound its work; the connection waits without a deadline.
    lowest().expires_never();
    auto self = this->shared_from_this();
    server_->router.dispatch(r, [self](HttpReply reply) {
      net::post(self->stream_.get_executor(), [self, reply = std::move(reply)]() mutable {
        self->write(std::move(reply), self->close_after_);
      });
    });
  }

  void write(HttpReply reply, bool close_after) {
    auto res = std::make_shared<http::response<http::string_body>>(
        static_cast<http::status>(reply.status), 11);
    for (auto& [k, v] : reply.headers) res->set(k, v);
    for (const auto& [k, v] : security_headers())
      if (res->find(k) == res->end()) res->set(k, v);
    if (secure_) make_cookies_secure(*res);
    res->set(http::field::content_type, reply.content_type);
    res->body() = std::move(reply.body);
    res->keep_alive(!close_after);
    res->prepare_payload();
    lowest().expires_after(std::chrono::milliseconds(options().write_timeout_ms));
    http::async_write(
        stream_, *res,
        [self = this->shared_from_this(), res, close_after](beast::error_code ec, std::size_t) {
          if (ec || close_after) return self->close();
          self->wait_for_request();
        });
  }

  // An answer that ends the connection (the stream may hold the rest of a bad request).
  void refuse(int status, const std::string& code, const std::string& message) {
    parser_.reset();
    buffer_.consume(buffer_.size());
    write(error_reply(status, code, message), true);
  }

  void fail(beast::error_code ec) {
    if (ec == http::error::body_limit)
      return refuse(413, "request_too_large",
                    "the request body is larger than serve.max_request_bytes (" +
                        std::to_string(options().max_request_bytes) + " bytes)");
    if (ec == http::error::header_limit)
      return refuse(431, "headers_too_large",
                    "the request line and headers are larger than " +
                        std::to_string(options().max_header_bytes) + " bytes");
    if (ec == http::error::bad_content_length)
      return refuse(400, "bad_content_length",
                    "Content-Length must be one non-negative number, given once");
    if (ec == http::error::bad_transfer_encoding)
      return refuse(501, "unsupported_transfer_encoding",
                    "this Transfer-Encoding is not supported (only chunked)");
    // Timeouts (the stream is closed already), end of stream, resets: nothing to answer.
    if (ec == beast::error::timeout || ec == http::error::end_of_stream ||
        ec == http::error::partial_message ||
        ec.category() != make_error_code(http::error::body_limit).category())
      return close();
    refuse(400, "bad_http", "malformed HTTP request: " + ec.message());
  }

  void close() {
    if constexpr (kTls) {
      // close_notify, bounded: a client that does not answer it is cut off.
      if (!shutting_down_) {
        shutting_down_ = true;
        lowest().expires_after(std::chrono::milliseconds(options().write_timeout_ms));
        stream_.async_shutdown(
            [self = this->shared_from_this()](beast::error_code) { self->close_socket(); });
        return;
      }
    }
    close_socket();
  }

  void close_socket() {
    beast::error_code ignored;
    lowest().socket().shutdown(tcp::socket::shutdown_both, ignored);
    lowest().close();
  }

  HttpTransport::Impl* server_;
  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::string peer_;
  bool close_after_ = false;
  bool secure_ = false;  ///< the current request's page is HTTPS (its cookies get Secure)
  bool shutting_down_ = false;
};

}  // namespace

void HttpTransport::Impl::accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!acceptor.is_open()) return;
    if (ec == net::error::no_descriptors ||
        ec == boost::system::errc::too_many_files_open_in_system ||
        ec == net::error::no_buffer_space || ec == net::error::no_memory)
      return out_of_descriptors();
    if (!ec) admit(std::move(socket));
    accept();
  });
}

void HttpTransport::Impl::out_of_descriptors() {
  if (spare_fd >= 0) {
    ::close(spare_fd);
    spare_fd = -1;
  }
  const int fd =
      ::accept4(acceptor.native_handle(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
  if (fd >= 0) {
    const std::string& text = out_of_descriptors_text;
    (void)::send(fd, text.data(), text.size(), MSG_NOSIGNAL);
    ::close(fd);
  }
  spare_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  backoff.expires_after(std::chrono::milliseconds(20));
  backoff.async_wait([this](beast::error_code ec) {
    if (!ec && acceptor.is_open()) accept();
  });
}

// Counts the connection against its address and the total; over a cap the client gets a 503
// written without waiting (a fresh socket's buffer takes it) and the connection is closed.
void HttpTransport::Impl::admit(tcp::socket socket) {
  beast::error_code ec;
  const auto endpoint = socket.remote_endpoint(ec);
  if (ec) return;
  std::string peer = endpoint.address().to_string();
  socket.set_option(tcp::no_delay(true), ec);
  std::string refusal;
  {
    std::lock_guard lock(mutex);
    const std::string subnet = subnet_of(peer);
    const std::size_t mine = per_address[peer], ours = per_subnet[subnet];
    // A listed proxy carries many clients: only the total caps it (docs/serve.md).
    const bool proxy = proxies.trusts(peer);
    if (proxy) {
      if (total >= options.max_connections)
        refusal =
            "the server has " + std::to_string(total) + " open connections (serve.max_connections)";
    } else if (mine >= options.max_connections_per_address)
      refusal = "this address has " + std::to_string(mine) +
                " open connections (serve.max_connections_per_address)";
    else if (ours >= options.max_connections_per_subnet)
      refusal = "the addresses of " + subnet + " have " + std::to_string(ours) +
                " open connections (serve.max_connections_per_subnet)";
    else if (total >= options.max_connections)
      refusal =
          "the server has " + std::to_string(total) + " open connections (serve.max_connections)";
    if (refusal.empty()) {
      ++per_address[peer];
      ++per_subnet[subnet];
      ++total;
    } else {
      if (mine == 0) per_address.erase(peer);
      if (ours == 0) per_subnet.erase(subnet);
    }
  }
  if (!refusal.empty()) {
    const std::string text = refusal_text(refusal);
    socket.non_blocking(true, ec);
    socket.write_some(net::buffer(text), ec);
    socket.shutdown(tcp::socket::shutdown_both, ec);
    socket.close(ec);
    return;
  }
  if (tls)
    std::make_shared<Connection<beast::ssl_stream<beast::tcp_stream>>>(
        this, beast::ssl_stream<beast::tcp_stream>(std::move(socket), *tls), std::move(peer))
        ->start();
  else
    std::make_shared<Connection<beast::tcp_stream>>(this, beast::tcp_stream(std::move(socket)),
                                                    std::move(peer))
        ->start();
}

HttpTransport::HttpTransport(TransportOptions options, const Router& router)
    : impl_(std::make_unique<Impl>(std::move(options), router)) {}

HttpTransport::~HttpTransport() = default;

int HttpTransport::bind(const std::string& host, int port) {
  beast::error_code ec;
  tcp::resolver resolver(impl_->io);
  const auto results =
      resolver.resolve(host, std::to_string(port), tcp::resolver::numeric_service, ec);
  auto fail = [&](const std::string& why) -> int {
    throw sdk::Error("serve_failed",
                     "cannot listen on " + host + ":" + std::to_string(port) + " (" + why + ")");
  };
  if (ec || results.empty()) return fail("not an address of this machine: " + ec.message());
  const tcp::endpoint endpoint = results.begin()->endpoint();
  auto& a = impl_->acceptor;
  a.open(endpoint.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(endpoint, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (!ec) a.non_blocking(true, ec);
  if (ec) return fail(ec.message());
  impl_->spare_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  return a.local_endpoint().port();
}

void HttpTransport::run() {
  impl_->accept();
  impl_->io.run();
}

void HttpTransport::stop() {
  Impl* impl = impl_.get();
  net::post(impl->io, [impl] {
    beast::error_code ec;
    impl->acceptor.close(ec);
    impl->io.stop();
  });
}

}  // namespace flipper::studio
