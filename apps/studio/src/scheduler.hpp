#pragma once
// Which request runs next (docs/studio.md §5). Jobs carry a key (a session's token, or the
// address that asks for a new session); jobs of one key run one at a time, in arrival order. A
// free worker takes the key that has used the least CPU time lately, so a user who sends cheap
// requests overtakes users whose requests are expensive. Each key has a CPU-time allowance
// (serve.cpu_ms_per_s, refilled continuously, at most serve.cpu_burst_ms banked): a key whose
// allowance is spent waits until it is positive again; that is the cost-aware limit beside the
// request rate. CPU time is the worker thread's (CLOCK_THREAD_CPUTIME_ID), so a request that
// waits for a lock or the disk costs nothing.
// Heavy keys (whose requests lately cost serve's heavy threshold of CPU each) may hold at most
// `workers - reserve` workers at once: the reserve stays free for cheap requests, so they never
// wait for an expensive one to finish. A key may be pinned to one worker (its state lives there);
// otherwise it prefers the worker that ran it last when that one is free (its kernel's caches are
// warm and the session need not move).
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace flipper::studio {

struct SchedulerOptions {
  int workers = 4;
  double cpu_ms_per_s = 500;   ///< allowance refill per key
  double cpu_burst_ms = 2000;  ///< allowance banked at most
  std::size_t max_queued_per_key = 8;
  int reserve = 0;       ///< workers heavy keys cannot take
  double heavy_ms = 20;  ///< a key is heavy when its requests cost this much CPU lately
};

class Scheduler {
 public:
  using Clock = std::chrono::steady_clock;
  /// A job gets the index of the worker that runs it.
  using Job = std::function<void(int worker)>;

  explicit Scheduler(SchedulerOptions options);
  ~Scheduler();  ///< stops the workers; queued jobs are dropped (their callbacks destroyed)
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  /// Queues `job` under `key`; false (job not queued) when the key already has
  /// max_queued_per_key jobs waiting. A key with `worker` >= 0 runs on that worker only.
  bool submit(const std::string& key, Job job, int worker = -1);
  /// The CPU allowance a key has now, in ms (tests and the benchmark).
  double allowance_ms(const std::string& key);

 private:
  struct Key {
    std::deque<Job> jobs;
    bool running = false;
    double allowance_ms = 0;
    double recent_ms = 0;  ///< CPU time used, decayed with a 10 s time constant
    Clock::time_point refilled;
    std::uint64_t arrival = 0;  ///< of its oldest waiting job: ties go to the older
    double cost_ms = 0;         ///< CPU per request, averaged (weight 1/2 to the last)
    int worker = -1;            ///< pinned to this worker (-1: any)
    int last_worker = -1;       ///< ran its last job
  };
  bool heavy(const Key& k) const { return k.cost_ms >= options_.heavy_ms; }
  void work(int index);
  void refill(Key& k, Clock::time_point now) const;
  /// The runnable key that used the least CPU lately; end() when none; `wake` gets the earliest
  /// time a spent key becomes runnable.
  std::map<std::string, Key>::iterator pick(int worker, Clock::time_point now,
                                            Clock::time_point& wake);

  SchedulerOptions options_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, Key> keys_;
  std::uint64_t arrivals_ = 0;
  int running_heavy_ = 0;
  std::vector<bool> worker_busy_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

/// CPU time this thread has used, in ms.
double thread_cpu_ms();

}  // namespace flipper::studio
