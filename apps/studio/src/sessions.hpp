#pragma once
// The sessions of `flipper serve` over its kernel pools (docs/studio.md §5): opening one (guests,
// logins, study enrolment), the registry's limits, moving a session to a free kernel of its pool,
// and destroying evicted sessions under their kernel's lock. The protocol endpoint (api.hpp),
// /sempre (sempre.hpp) and the study's endpoints (study_http.hpp) each use this, not one another.
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "flipper/studio/accounts.hpp"
#include "flipper/studio/server.hpp"
#include "http_types.hpp"
#include "kernel_pools.hpp"
#include "registry.hpp"

namespace flipper::studio {

class Study;
class Recorder;

class Sessions {
 public:
  /// kernels: group name -> config (a plain server: {"", config}).
  Sessions(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options,
           AccountStore& accounts);
  Sessions(const Sessions&) = delete;
  Sessions& operator=(const Sessions&) = delete;
  /// Stops the pools' workers (they use the sessions), then destroys every session.
  ~Sessions();

  /// Study mode: sessions are enrolled and every protocol exchange is handed to the recorder.
  void set_study(std::shared_ptr<Study> study, std::shared_ptr<Recorder> recorder) {
    study_ = std::move(study);
    recorder_ = std::move(recorder);
  }
  const std::shared_ptr<Recorder>& recorder() const { return recorder_; }
  const std::shared_ptr<Study>& study() const { return study_; }

  SessionRegistry& registry() { return registry_; }
  KernelPools& pools() { return pools_; }
  /// The kernels of every pool.
  std::size_t kernel_count() const { return pools_.kernel_count(); }

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

  /// Opens a session for `request` on kernel `k` (or its group's first kernel): a login's, or a
  /// guest's when the server has guests; enrolled in the study, if any. Null with `reply` set
  /// when it is refused (login_required, the registry's limits, the study's enrolment).
  std::shared_ptr<SessionEntry> open(const HttpRequest& request, const std::optional<Login>& login,
                                     Kernel& k, HttpReply& reply);
  /// Moves the entry's session onto kernel `k` (call under its lock): `k`'s extensions, then the
  /// studio's ops, as when it was opened.
  void move_to(SessionEntry& entry, Kernel& k);
  /// Destroys evicted sessions under their kernel's lock; a session whose kernel is busy waits
  /// for a later call (never for the kernel). Call without holding a kernel's lock.
  void bury_evicted();

 private:
  /// The studio's ops on the entry's session, over kernel `k`.
  void install_studio_ops(SessionEntry& entry, Kernel& k);

  ServeOptions options_;
  AccountStore& accounts_;
  KernelPools pools_;  ///< before the registry: its sessions go first
  std::mutex graves_mutex_;
  std::vector<std::shared_ptr<SessionEntry>> graves_;  ///< evicted, their kernel was busy
  SessionRegistry registry_;
  std::shared_ptr<Recorder> recorder_;
  std::shared_ptr<Study> study_;
};

}  // namespace flipper::studio
