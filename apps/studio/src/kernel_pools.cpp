#include "kernel_pools.hpp"

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <thread>

#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "studio_ops.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;

namespace {

// Every token of the core grammar plus its word classes: the vocabulary for "did you mean".
Json vocabulary(const kernel::Runtime& rt) {
  std::set<std::string> words;
  if (rt.core_grammar) {
    for (const auto& rule : rt.core_grammar->rules)
      for (const auto& s : rule->rhs)
        if (s.type == sdk::Symbol::Type::token) words.insert(s.text);
    for (const auto* list :
         {&rt.core_grammar->colors, &rt.core_grammar->shapes, &rt.core_grammar->directions})
      words.insert(list->begin(), list->end());
  }
  return Json(std::vector<std::string>(words.begin(), words.end()));
}

// The world menu (docs/studio.md "The page"): the *.json files of the config's world directory
// that this runtime's world plugin loads (a 3-D world is no choice on a 2-D server), each read
// within input.max_file_bytes and world.max_cells as a `world` request would be.
Json world_files(const kernel::Runtime& rt, const std::string& root) {
  Json out = Json::array();
  std::error_code ec;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(root, ec))
    if (e.is_regular_file() && e.path().extension() == ".json")
      names.insert(e.path().filename().string());
  for (const auto& n : names) {
    try {
      (void)kernel::load_world_file(rt, (fs::path(root) / n).string());
      out.push_back(n);
    } catch (const std::exception&) {
      // not a world of this runtime: left out of the menu
    }
  }
  return out;
}

// serve.kernels: 0 means the cores plus one kernel the heavy sessions cannot take. A store in
// memory is private to its connection: one kernel then.
// A study group has one kernel: its records are then in the order it answered, and a replay
// of them meets the same store (docs/studio.md §5).
int pool_size(const ServeOptions& options, const kernel::Config& config) {
  if (config.text(naturalization::keys::kLexiconPath) == ":memory:" || !options.study.empty())
    return 1;
  if (options.kernels > 0) return options.kernels;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) + 1;
}

// Heavy sessions may hold this many kernels at once: one core's worth less than the machine has,
// so a cheap request finds a free kernel and a free core (with every core busy with heavy
// queries, `move left` waited for the CPU: p99 up to 250 ms, against 5 ms; docs/studio.md §5).
int heavy_kernels(int kernels) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return kernels > 1 ? std::max(1, std::min(kernels - 1, cores - 1)) : 1;
}

}  // namespace

std::size_t kernel_bytes(std::size_t rules) {
  return (std::size_t{4} << 20) + rules * 1024;
}

KernelPools::KernelPools(const std::vector<std::pair<std::string, kernel::Config>>& groups,
                         const ServeOptions& options) {
  for (const auto& [group, config] : groups) {
    KernelPool& pool = pools_[group];
    const int n = pool_size(options, config);
    for (int i = 0; i < n; ++i) {
      auto k = std::make_unique<Kernel>();
      k->runtime = kernel::make_runtime(config);
      k->host = std::make_unique<wiring::SessionHost>(wiring::open_host(k->runtime));
      std::error_code ec;
      k->world_root =
          fs::weakly_canonical(fs::path(config.get(kernel::keys::kWorldFile)).parent_path(), ec)
              .string();
      k->max_world_bytes =
          world_bytes(static_cast<std::size_t>(config.get(kernel::keys::kMaxWorldCells)));
      k->vocabulary = vocabulary(*k->runtime);
      k->worlds = pool.kernels.empty() ? world_files(*k->runtime, k->world_root)
                                       : pool.kernels.front()->worlds;
      bytes_ += kernel_bytes(k->host->naturalizer->induced_rules().size());
      pool.kernels.push_back(std::move(k));
    }
    SchedulerOptions so;
    so.workers = n;
    so.reserve = n - heavy_kernels(n);
    so.cpu_ms_per_s = options.cpu_ms_per_s;
    so.cpu_burst_ms = options.cpu_burst_ms;
    pool.scheduler = std::make_unique<Scheduler>(so);
  }
}

KernelPools::~KernelPools() {
  stop_workers();
}

void KernelPools::stop_workers() {
  for (auto& [group, pool] : pools_) pool.scheduler.reset();
}

std::size_t KernelPools::kernel_count() const {
  std::size_t n = 0;
  for (const auto& [group, pool] : pools_) n += pool.kernels.size();
  return n;
}

KernelPool& KernelPools::pool_for(const std::string& group) {
  auto it = pools_.find(group);
  return it == pools_.end() ? pools_.begin()->second : it->second;
}

bool KernelPools::in_pool(const std::string& group, const Kernel& k) {
  const auto& kernels = pool_for(group).kernels;
  return std::any_of(kernels.begin(), kernels.end(),
                     [&](const std::unique_ptr<Kernel>& p) { return p.get() == &k; });
}

std::size_t KernelPools::session_budget(const ServeOptions& options) const {
  const std::size_t kernels = kernel_count();
  const std::size_t kernels_bytes = bytes_;
  const std::size_t budget = options.memory_budget_mb << 20;
  if (kernels_bytes * 2 > budget)
    throw sdk::Error(sdk::codes::kBadConfig,
                     std::to_string(kernels) + " kernels take " +
                         std::to_string((kernels_bytes + (1 << 20) - 1) >> 20) +
                         " MiB, more than half of serve.memory_budget_mb (" +
                         std::to_string(options.memory_budget_mb) +
                         " MiB): lower serve.kernels or raise the budget");
  return budget - kernels_bytes;
}

}  // namespace flipper::studio
