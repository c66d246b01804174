// The server's parts and its routes. The transport is http_transport.cpp, the protocol mapping
// api.cpp; a new page or API path is one line in add_routes().
#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "api.hpp"
#include "auth_http.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/studio/server.hpp"
#include "host_policy.hpp"
#include "http_transport.hpp"
#include "recorder.hpp"
#include "scheduler.hpp"
#include "sempre.hpp"
#include "static_files.hpp"
#include "study.hpp"
#include "study_http.hpp"

namespace flipper::studio {
namespace {

HttpReply static_reply(const StaticFiles& files, const HttpRequest& req) {
  const StaticFile* f = files.find(req.path);
  if (f == nullptr) return error_reply(404, "not_found", "no such page or API path");
  HttpReply r;
  r.content_type = f->content_type;
  r.body = f->body;
  r.set_header("Cache-Control", "no-cache");
  r.set_header("Content-Security-Policy",
               "default-src 'self'; img-src 'self' data:; frame-ancestors 'none'; "
               "base-uri 'none'; form-action 'self'");
  return r;
}

// Descriptors the server needs besides connections: the standard streams, the event loop's, each
// kernel's lexicon store (file, WAL and its index), the accounts store, the recording's files,
// the page's files while read, and the spare kept for refusing at EMFILE.
constexpr std::size_t kDescriptorsBesideConnections = 64;
constexpr std::size_t kDescriptorsPerKernel = 4;

// Raises the descriptor limit to its hard limit (a server should not fail at the common
// `ulimit -n 1024` when the system allows more) and returns it (docs/studio.md §2).
std::size_t raise_descriptor_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return 1024;
  if (limit.rlim_cur < limit.rlim_max) {
    rlimit raised = limit;
    raised.rlim_cur = limit.rlim_max;
    if (::setrlimit(RLIMIT_NOFILE, &raised) == 0) limit = raised;
  }
  return limit.rlim_cur == RLIM_INFINITY ? std::size_t{1} << 20
                                         : static_cast<std::size_t>(limit.rlim_cur);
}

}  // namespace

struct Server::Impl {
  ServeOptions options;
  std::unique_ptr<StaticFiles> files;
  std::unique_ptr<AccountStore> accounts;
  HostPolicy hosts;
  Router router;
  std::unique_ptr<HttpTransport> transport;
  // Destroyed before the transport: no worker answers into a transport that is gone.
  std::unique_ptr<Sessions> sessions;      ///< the kernel pools and their sessions (sessions.hpp)
  std::unique_ptr<Api> api;                ///< the session protocol over HTTP
  std::unique_ptr<AuthEndpoints> auth;     ///< logins and logouts (docs/accounts.md)
  std::unique_ptr<SempreEndpoint> sempre;  ///< serve.sempre: GET /sempre (docs/sempre.md)
  std::unique_ptr<StudyEndpoints> study;  ///< events and the researcher's view (docs/studio.md §7)
  std::unique_ptr<Scheduler> scheduler;   // destroyed first: its workers use the api
  /// Logins and logouts on a worker of their own: a password check (Argon2id, tens of ms of CPU)
  /// never holds a worker another request waits for (docs/accounts.md §2).
  std::unique_ptr<Scheduler> login_scheduler;
  std::size_t connection_cap = 0;  ///< serve.max_connections, lowered to fit the descriptors

  void add_routes() {
    Api* a = api.get();
    router.add("POST", "/api/v1/request",
               [a](const HttpRequest& r, const Respond& done) { a->request(r, done); });
    router.add("GET", "/api/v1/info",
               [a](const HttpRequest& r, const Respond& done) { a->info(r, done); });
    AuthEndpoints* auth_endpoints = auth.get();
    router.add("POST", "/api/v1/login",
               [auth_endpoints](const HttpRequest& r, const Respond& done) {
                 auth_endpoints->login(r, done);
               });
    router.add("POST", "/api/v1/logout",
               [auth_endpoints](const HttpRequest& r, const Respond& done) {
                 auth_endpoints->logout(r, done);
               });
    StudyEndpoints* s = study.get();
    router.add("POST", "/api/v1/study/event",
               [s](const HttpRequest& r, const Respond& done) { s->event(r, done); });
    router.add("GET", "/api/v1/study/overview",
               [s](const HttpRequest& r, const Respond& done) { s->overview(r, done); });
    router.add("POST", "/api/v1/study/close",
               [s](const HttpRequest& r, const Respond& done) { s->close(r, done); });
    router.add("POST", "/api/v1/study/invite",
               [s](const HttpRequest& r, const Respond& done) { s->invite(r, done); });
    router.add("POST", "/api/v1/study/end",
               [s](const HttpRequest& r, const Respond& done) { s->end(r, done); });
    router.add("POST", "/api/v1/study/next",
               [s](const HttpRequest& r, const Respond& done) { s->next(r, done); });
    router.add("GET", "/api/v1/study/lexicon",
               [s](const HttpRequest& r, const Respond& done) { s->lexicon(r, done); });
    router.add("POST", "/api/v1/study/lexicon/approve",
               [s](const HttpRequest& r, const Respond& done) { s->moderate(r, done, true); });
    router.add("POST", "/api/v1/study/lexicon/reject",
               [s](const HttpRequest& r, const Respond& done) { s->moderate(r, done, false); });
    router.add_prefix("GET", "/api/v1/study/recording/",
                      [s](const HttpRequest& r, const Respond& done) { s->recording(r, done); });
    if (sempre) {
      // On the plain kernel's worker, one request at a time per sessionId, never on the I/O
      // thread (docs/sempre.md, docs/studio.md §5).
      auto answer = [this, sessions_of = sessions.get(), s = sempre.get()](const HttpRequest& r,
                                                                           const Respond& done) {
        sessions_of->run_on_plain_kernel(
            "sempre:" + r.param("sessionId"),
            [s, r, own = hosts.allows_origin(r)] {
              return s->handle({r.method, r.raw_query, r.peer, r.origin, own});
            },
            done);
      };
      router.add("GET", "/sempre", answer);
      router.add("OPTIONS", "/sempre", answer);
    }
    const StaticFiles* f = files.get();
    router.fallback("GET",
                    [f](const HttpRequest& r, const Respond& done) { done(static_reply(*f, r)); });
    router.guard([this](const HttpRequest& r, HttpReply& reply) { return hosts.refuse(r, reply); });
  }
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
    // One read of the study file: its accounts are found from the study loaded here.
    study = Study::load(m.options.study);
    m.options.accounts = accounts_path(config, study->record_dir());
  }
  m.accounts = std::make_unique<AccountStore>(m.options.accounts);
  if (study) {
    std::error_code ec;
    std::filesystem::create_directories(study->record_dir(), ec);
    kernels = study->kernels(config);
  }
  SchedulerOptions so;
  so.workers = m.options.threads;
  so.cpu_ms_per_s = m.options.cpu_ms_per_s;
  so.cpu_burst_ms = m.options.cpu_burst_ms;
  m.scheduler = std::make_unique<Scheduler>(so);
  SchedulerOptions logins = so;
  logins.workers = 1;
  m.login_scheduler = std::make_unique<Scheduler>(logins);
  m.sessions = std::make_unique<Sessions>(kernels, m.options, *m.accounts);
  m.api = std::make_unique<Api>(*m.sessions, m.options, *m.accounts, *m.scheduler, m.hosts);
  m.auth = std::make_unique<AuthEndpoints>(m.options.login_days, *m.accounts, *m.login_scheduler,
                                           m.hosts);
  if (study) m.sessions->set_study(study, std::make_shared<Recorder>(study, kernels));
  m.study = std::make_unique<StudyEndpoints>(*m.sessions, *m.accounts, *m.scheduler, m.hosts);
  TransportOptions t;
  t.request_timeout_ms = m.options.request_timeout_ms;
  t.idle_timeout_ms = m.options.idle_timeout_ms;
  // The connection cap stays below the descriptor limit, so a flood meets a 503, never EMFILE.
  const std::size_t descriptors = raise_descriptor_limit();
  const std::size_t needed =
      kDescriptorsBesideConnections + kDescriptorsPerKernel * m.sessions->kernel_count();
  if (descriptors <= needed + 1)
    throw sdk::Error(sdk::codes::kBadConfig,
                     "the descriptor limit (" + std::to_string(descriptors) +
                         ", ulimit -n) leaves no room for connections: raise it");
  t.max_connections = std::min(m.options.max_connections, descriptors - needed);
  m.connection_cap = t.max_connections;
  t.max_connections_per_address = m.options.max_connections_per_address;
  t.max_connections_per_subnet = m.options.max_connections_per_subnet;
  t.max_request_bytes = m.options.max_request_bytes;
  t.tls_cert = m.options.tls_cert;
  t.tls_key = m.options.tls_key;
  t.behind_proxy = m.options.behind_proxy;
  m.transport = std::make_unique<HttpTransport>(t, m.router);
  if (m.options.sempre) m.sempre = std::make_unique<SempreEndpoint>(*m.sessions, m.options);
  m.add_routes();
}

Server::~Server() {
  // Workers first (they answer into the transport), then the endpoints they use, then the
  // sessions (whose destructor stops the kernels' workers before the sessions go).
  impl_->scheduler.reset();
  impl_->login_scheduler.reset();
  impl_->sempre.reset();
  impl_->study.reset();
  impl_->api.reset();
  impl_->sessions.reset();
}

const ServeOptions& Server::options() const {
  return impl_->options;
}

std::size_t Server::connection_cap() const {
  return impl_->connection_cap;
}

int Server::bind() {
  Impl& m = *impl_;
  const int port = m.transport->bind(m.options.host, m.options.port);
  m.hosts = HostPolicy(m.options.host, port, m.options.allowed_hosts);
  return port;
}

void Server::listen() {
  impl_->transport->run();
}

void Server::stop() {
  impl_->transport->stop();
}

}  // namespace flipper::studio
