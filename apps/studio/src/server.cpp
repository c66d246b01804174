// httplib wiring: routes, limits, threads. The protocol mapping itself lives in api.cpp.
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <filesystem>
#include <iostream>

#include "api.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/studio/server.hpp"
#include "recorder.hpp"
#include "sempre.hpp"
#include "static_files.hpp"
#include "study.hpp"

namespace flipper::studio {
namespace {

HttpRequest to_request(const httplib::Request& req) {
  HttpRequest r;
  r.session = req.get_param_value("session");
  r.group = req.get_param_value("group");
  r.origin = req.get_header_value("Origin");
  r.host = req.get_header_value("Host");
  r.sec_fetch_site = req.get_header_value("Sec-Fetch-Site");
  r.body = req.body;
  return r;
}

void send(httplib::Response& res, const HttpReply& reply) {
  res.status = reply.status;
  for (const auto& [k, v] : reply.headers) res.set_header(k, v);
  res.set_content(reply.body, "application/json");
}

// Errors httplib produces itself (too large, no route) get the protocol's error object too.
std::pair<std::string, std::string> transport_error(int status, std::size_t max_bytes) {
  switch (status) {
    case 413:
      return {"request_too_large", "the request body is larger than serve.max_request_bytes (" +
                                       std::to_string(max_bytes) + " bytes)"};
    case 404:
      return {"not_found", "no such page or API path"};
    case 405:
      return {"method_not_allowed", "this path does not take that method"};
    default:
      return {"http_error", "HTTP status " + std::to_string(status)};
  }
}

// httplib 0.11 listens with a backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG, compiled into Debian's
// library): a hundred users connecting at once overflow it and wait for SYN retransmits (1 s).
// Linux lets listen() be called again to change the backlog, so find the listening socket of
// `port` among our descriptors and raise it.
void raise_listen_backlog(int port) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
    int fd = -1;
    try {
      fd = std::stoi(entry.path().filename().string());
    } catch (...) {
      continue;
    }
    int listening = 0;
    socklen_t len = sizeof listening;
    if (getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len) != 0 || !listening) continue;
    sockaddr_storage addr{};
    socklen_t alen = sizeof addr;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &alen) != 0) continue;
    int bound = -1;
    if (addr.ss_family == AF_INET)
      bound = ntohs(reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
    else if (addr.ss_family == AF_INET6)
      bound = ntohs(reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port);
    if (bound == port) ::listen(fd, SOMAXCONN);
  }
}

}  // namespace

struct Server::Impl {
  ServeOptions options;
  std::unique_ptr<StaticFiles> files;
  std::unique_ptr<Api> api;
  std::unique_ptr<SempreEndpoint> sempre;  ///< serve.sempre: GET /sempre
  httplib::Server http;
  bool bound = false;
};

Server::Server(const kernel::Config& config) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = ServeOptions::from_config(config);
  m.files = std::make_unique<StaticFiles>(find_web_dir(m.options.web_dir));
  std::shared_ptr<Study> study;
  std::vector<std::pair<std::string, kernel::Config>> kernels{{"", config}};
  if (!m.options.study.empty()) {
    if (m.options.sempre)
      throw sdk::Error(sdk::codes::kBadConfig,
                       "serve.sempre cannot be combined with serve.study: /sempre sessions belong "
                       "to no study group");
    study = Study::load(m.options.study);
    std::error_code ec;
    std::filesystem::create_directories(study->record_dir(), ec);
    kernels = study->kernels(config);
  }
  m.api = std::make_unique<Api>(kernels, m.options);
  if (study) {
    m.api->set_study(study);
    m.api->set_recorder(std::make_shared<Recorder>(study));
  }

  const int threads = m.options.threads;
  m.http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  m.http.set_payload_max_length(m.options.max_request_bytes);
  m.http.set_keep_alive_max_count(100000);
  m.http.set_keep_alive_timeout(2);
  m.http.set_read_timeout(10, 0);
  m.http.set_write_timeout(10, 0);
  m.http.set_tcp_nodelay(true);

  Api* api = m.api.get();
  m.http.Post("/api/v1/request", [api](const httplib::Request& req, httplib::Response& res) {
    send(res, api->request(to_request(req)));
  });
  m.http.Get("/api/v1/info", [api](const httplib::Request& req, httplib::Response& res) {
    send(res, api->info(to_request(req)));
  });
  if (m.options.sempre) {  // docs/sempre.md; registered before the page's catch-all route
    m.sempre = std::make_unique<SempreEndpoint>(*m.api, m.options);
    auto sempre = [endpoint = m.sempre.get()](const httplib::Request& req, httplib::Response& res) {
      const std::size_t q = req.target.find('?');
      send(res, endpoint->handle({req.method, q == std::string::npos ? std::string()
                                                                     : req.target.substr(q + 1)}));
    };
    m.http.Get("/sempre", sempre);
    m.http.Options("/sempre", sempre);
  }
  const StaticFiles* files = m.files.get();
  m.http.Get(".*", [files](const httplib::Request& req, httplib::Response& res) {
    const StaticFile* f = files->find(req.path);
    if (f == nullptr) {
      res.status = 404;
      return;
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("Content-Security-Policy", "default-src 'self'; img-src 'self' data:");
    res.set_content(f->body, f->content_type.c_str());
  });
  const std::size_t max_bytes = m.options.max_request_bytes;
  m.http.set_error_handler(httplib::Server::HandlerWithResponse(
      [max_bytes](const httplib::Request&, httplib::Response& res) {
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        const auto [code, message] = transport_error(res.status, max_bytes);
        res.set_content(error_body(code, message), "application/json");
        return httplib::Server::HandlerResponse::Handled;
      }));
  m.http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown exception";
        try {
          std::rethrow_exception(ep);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        res.status = 500;
        res.set_content(error_body("internal", "internal error: " + what), "application/json");
      });
}

Server::~Server() = default;

const ServeOptions& Server::options() const {
  return impl_->options;
}

int Server::bind() {
  Impl& m = *impl_;
  int port = m.options.port;
  if (port == 0) {
    port = m.http.bind_to_any_port(m.options.host);
  } else if (!m.http.bind_to_port(m.options.host, port)) {
    port = -1;
  }
  if (port < 0)
    throw sdk::Error("serve_failed", "cannot listen on " + m.options.host + ":" +
                                         std::to_string(m.options.port) +
                                         " (in use, or not an address of this machine)");
  raise_listen_backlog(port);
  m.bound = true;
  return port;
}

void Server::listen() {
  impl_->http.listen_after_bind();
}

void Server::stop() {
  impl_->http.stop();
}

}  // namespace flipper::studio
