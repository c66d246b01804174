// flipper dds, in the dds front-end module (frontend_module.hpp): a DDS node answering
// session-protocol requests from rt/<ns>/flipper/request on rt/<ns>/flipper/answer
// (apps/dds/request_node.hpp), with the config's other DDS services (plans, lexicon replication).
// Runs until SIGINT/SIGTERM.
#include <semaphore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <thread>

#include "commands.hpp"
#include "common.hpp"
#include "dds_node_services.hpp"
#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/request_node.hpp"
#include "flipper/kernel/runtime.hpp"
#include "sanitizer_build.hpp"

namespace flipper::cli {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
sem_t g_signalled;  // posted by the handler (sem_post is async-signal-safe)
extern "C" void on_signal(int) {
  g_stop.store(true);
  sem_post(&g_signalled);
}

// The stop bound (docs/ros2.md, "Stopping"): from SIGINT/SIGTERM to the process's exit.
constexpr std::chrono::milliseconds kStopLimit{2000};
// Of it, the longest wait for the readers to acknowledge the answers already written.
constexpr std::chrono::milliseconds kFlushLimit{1000};
// And the longest DDS teardown after the flush: Cyclone's participant deletion joins its receive
// threads, and a thread blocked on a multicast socket that Cyclone's wake-up packet never reaches
// (a user config that turns multicast on for `lo`) is never joined. Everything acknowledged is
// flushed (answers) or durable (SQLite) by then, so leaving the rest of the teardown undone loses
// nothing.
constexpr std::chrono::milliseconds kTeardownLimit{500};

// Bounds the stop: armed by the signal, it ends the process with exit 0 once the deadline
// passes, saying so; `exit_by` brings the deadline forward (the teardown's own limit).
class StopWatchdog {
 public:
  StopWatchdog()
      : thread_([this] {
          while (sem_wait(&g_signalled) != 0) {
          }
          std::unique_lock<std::mutex> lock(mutex_);
          if (done_) return;
          deadline_ = std::min(deadline_, Clock::now() + kStopLimit);
          while (!done_)
            if (changed_.wait_until(lock, deadline_) == std::cv_status::timeout &&
                Clock::now() >= deadline_) {
              std::cerr << "flipper dds: the stop passed its bound (" << kStopLimit.count()
                        << " ms from the signal, " << kTeardownLimit.count()
                        << " ms for the DDS teardown); exiting without the rest of it" << std::endl;
              std::_Exit(kExitOk);
            }
        }) {}
  StopWatchdog(const StopWatchdog&) = delete;
  StopWatchdog& operator=(const StopWatchdog&) = delete;
  void exit_by(Clock::time_point deadline) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      deadline_ = std::min(deadline_, deadline);
    }
    changed_.notify_all();
  }
  ~StopWatchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    changed_.notify_all();
    sem_post(&g_signalled);  // wakes the thread when no signal came
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool done_ = false;
  Clock::time_point deadline_ = Clock::time_point::max();
  std::thread thread_;  // last: it starts once the members it uses exist
};

}  // namespace

int dds_node_main(const CommonOptions& opts) {
  sem_init(&g_signalled, 0, 0);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  // Declared first, so destroyed last: it bounds the destructors below.
  StopWatchdog watchdog;
  set_server_isolation();  // docs/plugins-untrusted.md §6
  wiring::SessionHost host = wiring::open_host(config_file(opts), opts.overrides);
  const NodeServices services = NodeServices::start(host, /*force_participant=*/true);
  dds::RequestNode node(
      services.participant, [&] { return services.open(host); }, std::cerr,
      host.runtime->config.get(dds::keys::kNamespace));
  std::cerr << "flipper dds: serving " << node.request_topic() << " -> " << node.answer_topic()
            << " on DDS domain " << services.participant->domain() << std::endl;
  node.run(g_stop);
  const bool flushed = node.flush(kFlushLimit);
  std::cerr << "flipper dds: stopped after " << node.answered() << " answers, " << node.dropped()
            << " dropped requests" << (flushed ? "; every answer acknowledged" : "") << std::endl;
  watchdog.exit_by(Clock::now() + kTeardownLimit);
  return kExitOk;
}

}  // namespace flipper::cli
