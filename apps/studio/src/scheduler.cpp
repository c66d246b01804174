// Fair, cost-aware job scheduling for the studio's workers (scheduler.hpp, docs/studio.md §5).
#include "scheduler.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>

namespace flipper::studio {

namespace {
// "Lately": CPU time counts with weight e^(-age / 10 s) when choosing who runs next.
constexpr double kRecentSeconds = 10;
}  // namespace

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

Scheduler::Scheduler(SchedulerOptions options)
    : options_(options), worker_busy_(static_cast<std::size_t>(std::max(1, options.workers))) {
  for (int i = 0; i < std::max(1, options_.workers); ++i)
    workers_.emplace_back([this, i] { work(i); });
}

Scheduler::~Scheduler() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  for (auto& w : workers_) w.join();
}

void Scheduler::refill(Key& k, Clock::time_point now) const {
  const double s = std::chrono::duration<double>(now - k.refilled).count();
  k.allowance_ms = std::min(options_.cpu_burst_ms, k.allowance_ms + s * options_.cpu_ms_per_s);
  k.recent_ms *= std::exp(-s / kRecentSeconds);
  k.refilled = now;
}

bool Scheduler::submit(const std::string& key, Job job, int worker) {
  {
    std::lock_guard lock(mutex_);
    const auto now = Clock::now();
    auto [it, fresh] = keys_.try_emplace(key);
    Key& k = it->second;
    if (fresh) {
      k.allowance_ms = options_.cpu_burst_ms;
      k.refilled = now;
    }
    if (k.jobs.size() >= options_.max_queued_per_key) return false;
    k.worker = worker;
    if (k.jobs.empty()) k.arrival = ++arrivals_;
    k.jobs.push_back(std::move(job));
  }
  cv_.notify_all();  // the one worker that may take it (pinned, reserve) must hear it
  return true;
}

double Scheduler::allowance_ms(const std::string& key) {
  std::lock_guard lock(mutex_);
  auto it = keys_.find(key);
  if (it == keys_.end()) return options_.cpu_burst_ms;
  refill(it->second, Clock::now());
  return it->second.allowance_ms;
}

std::map<std::string, Scheduler::Key>::iterator Scheduler::pick(int worker, Clock::time_point now,
                                                                Clock::time_point& wake) {
  auto best = keys_.end();
  const int workers = static_cast<int>(workers_.size());
  const bool heavy_allowed = running_heavy_ < std::max(1, workers - options_.reserve);
  wake = Clock::time_point::max();
  for (auto it = keys_.begin(); it != keys_.end();) {
    Key& k = it->second;
    if (k.running) {
      ++it;
      continue;
    }
    refill(k, now);
    if (k.jobs.empty()) {
      // Idle and paid up: nothing to remember (a fresh key starts the same).
      it = k.allowance_ms >= options_.cpu_burst_ms && k.recent_ms < 0.01 ? keys_.erase(it)
                                                                         : std::next(it);
      continue;
    }
    const bool its_worker_free = k.last_worker >= 0 && k.last_worker != worker &&
                                 !worker_busy_[static_cast<std::size_t>(k.last_worker)];
    if ((k.worker >= 0 && k.worker != worker) || (heavy(k) && !heavy_allowed) || its_worker_free) {
      // Another worker's (pinned, or free and warm for it), or it waits for a heavy slot: a
      // finishing job wakes everyone.
      ++it;
      continue;
    }
    if (k.allowance_ms <= 0) {
      const auto until = now + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double, std::milli>(
                                       -k.allowance_ms / options_.cpu_ms_per_s * 1000.0 + 1.0));
      wake = std::min(wake, until);
    } else if (best == keys_.end() || k.recent_ms < best->second.recent_ms ||
               (k.recent_ms == best->second.recent_ms && k.arrival < best->second.arrival)) {
      best = it;
    }
    ++it;
  }
  return best;
}

void Scheduler::work(int index) {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (stopping_) return;
    Clock::time_point wake;
    auto it = pick(index, Clock::now(), wake);
    if (it == keys_.end()) {
      if (wake == Clock::time_point::max())
        cv_.wait(lock);
      else
        cv_.wait_until(lock, wake);
      continue;
    }
    const std::string key = it->first;
    Job job = std::move(it->second.jobs.front());
    it->second.jobs.pop_front();
    it->second.running = true;
    it->second.last_worker = index;
    worker_busy_[static_cast<std::size_t>(index)] = true;
    const bool was_heavy = heavy(it->second);
    running_heavy_ += was_heavy;
    lock.unlock();
    // Keys that waited for this worker (it ran them last) may now go to another free one.
    cv_.notify_all();
    const double cpu0 = thread_cpu_ms();
    job(index);
    job = nullptr;  // its captures (a connection) are released outside the lock
    const double used = thread_cpu_ms() - cpu0;
    lock.lock();
    Key& k = keys_[key];
    refill(k, Clock::now());
    k.allowance_ms -= used;
    k.recent_ms += used;
    k.cost_ms = (k.cost_ms + used) / 2;
    k.running = false;
    running_heavy_ -= was_heavy;
    worker_busy_[static_cast<std::size_t>(index)] = false;
    if (!k.jobs.empty()) k.arrival = ++arrivals_;
    cv_.notify_all();  // a heavy slot or a pinned key's worker may be free now
  }
}

}  // namespace flipper::studio
