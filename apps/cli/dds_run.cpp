// flipper dds, in the dds front-end module (frontend_module.hpp): a DDS node answering
// session-protocol requests from rt/<ns>/flipper/request on rt/<ns>/flipper/answer
// (apps/dds/request_node.hpp), with the config's other DDS services (plans, lexicon replication).
// Runs until SIGINT/SIGTERM.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "dds_node_services.hpp"
#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/request_node.hpp"
#include "flipper/kernel/runtime.hpp"

namespace flipper::cli {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) {
  g_stop.store(true);
}

// How long the DDS teardown after "stopped" may take (docs/ros2.md).
constexpr std::chrono::seconds kTeardownLimit{5};

// Bounds the teardown: Cyclone's participant deletion joins its receive threads, and a thread
// blocked on a multicast socket that Cyclone's wake-up packet never reaches (a user config that
// turns multicast on for `lo`) is never joined, so the process printed "stopped" and hung. Past
// the limit the process exits without the rest of the teardown, saying so; its answers were
// sent before "stopped".
class TeardownWatchdog {
 public:
  explicit TeardownWatchdog(std::chrono::seconds limit)
      : thread_([this, limit] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (done_cv_.wait_for(lock, limit, [this] { return done_; })) return;
          std::cerr << "flipper dds: the DDS teardown did not finish within " << limit.count()
                    << " s; exiting without it" << std::endl;
          std::_Exit(kExitOk);
        }) {}
  TeardownWatchdog(const TeardownWatchdog&) = delete;
  TeardownWatchdog& operator=(const TeardownWatchdog&) = delete;
  ~TeardownWatchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    done_cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable done_cv_;
  bool done_ = false;
  std::thread thread_;  // last: it starts once the members it uses exist
};

}  // namespace

int dds_node_main(const CommonOptions& opts) {
  // Declared first, so destroyed last: armed after "stopped", it bounds the destructors below.
  std::optional<TeardownWatchdog> watchdog;
  kernel::set_auto_isolation(kernel::Isolation::process);  // docs/plugins-untrusted.md §6
  wiring::SessionHost host = wiring::open_host(config_file(opts), opts.overrides);
  const NodeServices services = NodeServices::start(host, /*force_participant=*/true);
  dds::RequestNode node(
      services.participant, [&] { return services.open(host); }, std::cerr,
      host.runtime->config.get(dds::keys::kNamespace));
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::cerr << "flipper dds: serving " << node.request_topic() << " -> " << node.answer_topic()
            << " on DDS domain " << services.participant->domain() << std::endl;
  node.run(g_stop);
  std::cerr << "flipper dds: stopped after " << node.answered() << " answers, " << node.dropped()
            << " dropped requests" << std::endl;
  watchdog.emplace(kTeardownLimit);
  return kExitOk;
}

}  // namespace flipper::cli
