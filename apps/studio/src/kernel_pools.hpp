#pragma once
// The kernels of `flipper serve` (docs/studio.md §5): one runtime and lexicon connection each,
// grouped in pools (a plain server has one, group ""; a study one per group), each pool with the
// scheduler whose worker i runs on kernel i. What a kernel costs of serve.memory_budget_mb is
// charged here; the sessions get the rest (sessions.hpp).
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/studio/server.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "scheduler.hpp"

namespace flipper::studio {

/// One runtime and lexicon connection; the kernels of one pool share a config and a store.
struct Kernel {
  std::shared_ptr<kernel::Runtime> runtime;
  std::unique_ptr<wiring::SessionHost> host;
  std::string world_root;  ///< `world` requests may name files under this directory only
  std::size_t max_world_bytes = 0;
  kernel::Json vocabulary;  ///< for "did you mean" (computed once)
  kernel::Json worlds;      ///< the world menu: files of world_root this runtime loads
  std::mutex mutex;         ///< one request at a time
};

/// The kernels of one lexicon mode and their scheduler: worker i runs on kernel i, so the fair
/// choice is made when a kernel is free, not before a worker then waits for it (docs/studio.md §5).
struct KernelPool {
  std::vector<std::unique_ptr<Kernel>> kernels;
  std::unique_ptr<Scheduler> scheduler;
};

/// What a kernel is charged of serve.memory_budget_mb (docs/studio.md §5): measured, one more
/// kernel over an empty store adds ~0.7 MiB of resident memory and each stored rule ~1 KiB
/// (the 100k-rule store: 104 MiB against 11.5 MiB without rules); 4 MiB covers the runtime with
/// its caches' slack.
std::size_t kernel_bytes(std::size_t rules);

/// Every pool of a server, built from one config per group (a plain server: {"", config}).
class KernelPools {
 public:
  KernelPools(const std::vector<std::pair<std::string, kernel::Config>>& groups,
              const ServeOptions& options);
  KernelPools(const KernelPools&) = delete;
  KernelPools& operator=(const KernelPools&) = delete;
  ~KernelPools();

  /// The pool of `group`; an unknown group gets the first pool.
  KernelPool& pool_for(const std::string& group);
  /// Whether `k` is one of `group`'s kernels.
  bool in_pool(const std::string& group, const Kernel& k);
  /// The kernels of every pool.
  std::size_t kernel_count() const;
  /// What the kernels leave of serve.memory_budget_mb for sessions; bad_config when they would
  /// take more than half of it.
  std::size_t session_budget(const ServeOptions& options) const;
  /// Stops every pool's workers (they use the sessions, which the caller destroys next).
  void stop_workers();

 private:
  std::map<std::string, KernelPool> pools_;
  std::size_t bytes_ = 0;  ///< kernel_bytes of every kernel, at start
};

}  // namespace flipper::studio
