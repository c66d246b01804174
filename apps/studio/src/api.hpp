#pragma once
// The HTTP mapping of the session protocol (docs/serve.md, docs/studio.md): protocol dispatch and
// sessions, independent of the HTTP library: the routes take an HttpRequest and answer through a
// callback. Its parts: the kernel pools (kernel_pools.hpp), study enrolment (enrolment.hpp), the
// login cookie (cookies.hpp); logins are auth_http.hpp, the study's endpoints study_http.hpp.
// Protocol requests run on a kernel pool's workers, one at a time per session; each kernel is
// used by one request at a time (its parser, scorer, planner caches and naturalizer are not
// thread-safe), and a session moves to whichever kernel of its pool is free (docs/studio.md §5).
#include <atomic>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipper/studio/accounts.hpp"
#include "flipper/studio/server.hpp"
#include "host_policy.hpp"
#include "http_types.hpp"
#include "kernel_pools.hpp"
#include "registry.hpp"
#include "scheduler.hpp"

namespace flipper::studio {

class Study;
class Recorder;

class Api {
 public:
  /// kernels: group name -> config (a plain server: {"", config}).
  /// `scheduler` runs the work that needs no kernel (logins, info); each kernel has its own.
  Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options,
      AccountStore& accounts, Scheduler& scheduler, const HostPolicy& hosts);
  ~Api();

  /// POST /api/v1/request[?session=TOKEN]
  void request(const HttpRequest& request, const Respond& respond);
  /// GET /api/v1/info[?session=TOKEN]: what the page needs besides the protocol.
  void info(const HttpRequest& request, const Respond& respond);

  /// Runs `f(kernel)` with the plain server's kernel under its lock (call on a worker, e.g. from
  /// a job of run_on_plain_kernel): the /sempre endpoint (sempre.hpp) keeps its own sessions over
  /// that kernel.
  template <class F>
  decltype(auto) with_kernel(F&& f) {
    Kernel& k = *pools_.pool_for(std::string()).kernels.front();
    std::lock_guard lock(k.mutex);
    return f(k);
  }
  /// Runs `f(kernel)` with study group `group`'s first kernel under its lock (an unknown group:
  /// the first pool's): the researcher's lexicon page reads and moderates its lexicon there.
  template <class F>
  decltype(auto) with_group_kernel(const std::string& group, F&& f) {
    Kernel& k = *pools_.pool_for(group).kernels.front();
    std::lock_guard lock(k.mutex);
    return f(k);
  }
  /// Queues `job` on the plain pool's first kernel under `key` (one job at a time per key, the
  /// least CPU-hungry key first) and answers its reply; 429 `session_busy` when the key already
  /// has requests waiting.
  void run_on_plain_kernel(const std::string& key, std::function<HttpReply()> job,
                           const Respond& respond);

  /// Study mode: every protocol exchange is handed to the recorder.
  void set_recorder(std::shared_ptr<Recorder> recorder) { recorder_ = std::move(recorder); }
  void set_study(std::shared_ptr<Study> study) { study_ = std::move(study); }
  const std::shared_ptr<Recorder>& recorder() const { return recorder_; }
  const std::shared_ptr<Study>& study() const { return study_; }
  AccountStore& accounts() { return accounts_; }

  SessionRegistry& registry() { return registry_; }
  /// The kernels of every pool.
  std::size_t kernel_count() const { return pools_.kernel_count(); }
  /// Destroys evicted sessions under their kernel's lock; a session whose kernel is busy waits
  /// for a later call (never for the kernel). Call without holding a kernel's lock.
  void bury_evicted();

 private:
  /// The job of one protocol request, on the worker of kernel `k`.
  HttpReply serve(const HttpRequest& request, Kernel& k);
  std::shared_ptr<SessionEntry> open_session(const HttpRequest& request,
                                             const std::optional<Login>& login, Kernel& k,
                                             HttpReply& reply);
  /// The studio's ops on the entry's session, over kernel `k`.
  void install_studio_ops(SessionEntry& entry, Kernel& k);
  /// Moves the entry's session onto kernel `k` (under its lock): `k`'s extensions, then the
  /// studio's ops, as when it was opened.
  void install_ops(SessionEntry& entry, Kernel& k);
  HttpReply run(SessionEntry& entry, Kernel& free, const HttpRequest& request);
  HttpReply info_reply(const HttpRequest& request);

  ServeOptions options_;
  AccountStore& accounts_;
  Scheduler& scheduler_;
  const HostPolicy& hosts_;
  KernelPools pools_;  ///< before the registry: its sessions go first
  std::mutex graves_mutex_;
  std::vector<std::shared_ptr<SessionEntry>> graves_;  ///< evicted, their kernel was busy
  SessionRegistry registry_;
  std::shared_ptr<Recorder> recorder_;
  std::shared_ptr<Study> study_;
  std::atomic<std::uint64_t> new_requests_{0};
};

}  // namespace flipper::studio
