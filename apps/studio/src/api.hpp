#pragma once
// The HTTP mapping of the session protocol and of logins (README "Flipper Studio",
// docs/accounts.md, docs/studio.md), independent of the HTTP library: the routes take an
// HttpRequest and answer through a callback. Protocol requests run on the scheduler's workers,
// one at a time per session; each kernel (one per lexicon mode) is used by one request at a time
// (its parser, scorer, planner caches and naturalizer are not thread-safe).
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipper/studio/accounts.hpp"
#include "flipper/studio/server.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "host_policy.hpp"
#include "http_types.hpp"
#include "registry.hpp"
#include "scheduler.hpp"

namespace flipper::studio {

class Study;
class Recorder;

/// One kernel per lexicon mode: a plain server has one ("" group), a study one per group.
struct Kernel {
  std::shared_ptr<kernel::Runtime> runtime;
  std::unique_ptr<kernel::SessionHost> host;
  std::string world_root;  ///< `world` requests may name files under this directory only
  std::size_t max_world_bytes = 0;
  kernel::Json vocabulary;  ///< for "did you mean" (computed once)
  std::mutex mutex;         ///< one request at a time
  /// Its own worker: the fair choice is made when the kernel is free, not before a worker then
  /// waits for it (docs/studio.md §5).
  std::unique_ptr<Scheduler> scheduler;
};

class Api {
 public:
  /// kernels: group name -> config (a plain server: {"", config}).
  /// `scheduler` runs the work that needs no kernel (logins, info); each kernel has its own.
  Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options,
      AccountStore& accounts, Scheduler& scheduler, const HostPolicy& hosts);
  ~Api();

  /// POST /api/v1/request[?session=TOKEN]
  void request(const HttpRequest& request, Respond respond);
  /// GET /api/v1/info[?session=TOKEN]: what the page needs besides the protocol.
  void info(const HttpRequest& request, Respond respond);
  /// POST /api/v1/login {"name","password"} or {"code"}: a login cookie.
  void login(const HttpRequest& request, Respond respond);
  /// POST /api/v1/logout: ends the cookie's login.
  void logout(const HttpRequest& request, Respond respond);

  /// Runs `f(kernel)` with the plain server's kernel under its lock (call on a worker, e.g. from
  /// a job of run_on_plain_kernel): the /sempre endpoint (sempre.hpp) keeps its own sessions over
  /// that kernel.
  template <class F>
  decltype(auto) with_kernel(F&& f) {
    Kernel& k = kernel_for(std::string());
    std::lock_guard lock(k.mutex);
    return f(k);
  }
  /// Queues `job` on the plain kernel's scheduler under `key` (one job at a time per key, the
  /// least CPU-hungry key first) and answers its reply; 429 `session_busy` when the key already
  /// has requests waiting.
  void run_on_plain_kernel(const std::string& key, std::function<HttpReply()> job, Respond respond);

  /// Study mode: every protocol exchange is handed to the recorder.
  void set_recorder(std::shared_ptr<Recorder> recorder) { recorder_ = std::move(recorder); }
  void set_study(std::shared_ptr<Study> study) { study_ = std::move(study); }

  SessionRegistry& registry() { return registry_; }

 private:
  Kernel& kernel_for(const std::string& group);
  /// The job of one protocol request, on a worker.
  HttpReply serve(const HttpRequest& request);
  std::shared_ptr<SessionEntry> open_session(const HttpRequest& request,
                                             const std::optional<Login>& login, HttpReply& reply);
  HttpReply run(SessionEntry& entry, const HttpRequest& request);
  HttpReply login_reply(const HttpRequest& request);
  /// Destroys evicted sessions under their kernel's lock.
  void bury_evicted();
  bool login_allowed(const std::string& address);

  ServeOptions options_;
  AccountStore& accounts_;
  Scheduler& scheduler_;
  const HostPolicy& hosts_;
  std::map<std::string, std::unique_ptr<Kernel>> kernels_;
  SessionRegistry registry_;
  std::shared_ptr<Recorder> recorder_;
  std::shared_ptr<Study> study_;
  std::mutex study_mutex_;  ///< the study's assignment and the recorder
  std::atomic<std::uint64_t> new_requests_{0};
  std::mutex login_mutex_;
  std::map<std::string, std::pair<double, Clock::time_point>> login_buckets_;
};

/// The login token in a Cookie header ("" when none).
std::string login_cookie(const std::string& cookie_header);
/// A header-safe form of a name: anything but letters, digits, '.', '_' and '-' as %XX.
std::string header_safe(const std::string& name);

}  // namespace flipper::studio
