#pragma once
/// @file stop.hpp
/// When to give up (docs/planners.md §2): an expansion budget (work), a CPU-time budget on the
/// request thread's CPU clock, a cancel flag and a far wall-clock backstop, any of which stops.
/// The budgets decide answers the same on a quiet or a busy machine; the backstop only ends
/// runaways (a hang, a thread that never gets the CPU), and whatever stopped for time says which
/// limit fired (`StopCause`).

#include <pthread.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>

#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// What stopped work for time (protocol field `stopped`, docs/protocol.md "Errors").
/// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
enum class StopCause {
  none = 0,           ///< nothing fired
  cancelled = 1,      ///< the cancel flag was set
  cpu_budget = 2,     ///< the request thread used its CPU-time budget
  wall_backstop = 3,  ///< the far wall-clock backstop passed (a runaway, or a starved thread)
};
/// "none", "cancelled", "cpu_budget", "wall_backstop".
FLIPPER_SDK_API const char* to_string(StopCause c);

/// The CPU time a clock has counted: CLOCK_THREAD_CPUTIME_ID (the calling thread) or a clock
/// named by pthread_getcpuclockid (a given thread, read from any thread). A syscall (about 0.3 µs):
/// poll it every few hundred steps of work, as StopCondition's users do.
inline std::chrono::nanoseconds cpu_time(clockid_t clock = CLOCK_THREAD_CPUTIME_ID) {
  timespec t{};
  if (clock_gettime(clock, &t) != 0) return std::chrono::nanoseconds::max();  // fires: stop
  return std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec);
}

/// The calling thread's CPU clock as a clock any thread can read.
inline clockid_t this_thread_cpu_clock() {
  clockid_t c = CLOCK_THREAD_CPUTIME_ID;
  if (pthread_getcpuclockid(pthread_self(), &c) != 0) return CLOCK_THREAD_CPUTIME_ID;
  return c;
}

/// When to give up. The expansion budget is work and the CPU budget counts the request thread's
/// CPU time (plugins run on the request thread; CPU a plugin spends on threads of its own is not
/// counted), so neither depends on load; the wall-clock `deadline` is a far backstop against
/// hangs. A planner stopped by any of them answers `stopped`, never a result it would not give
/// with more time, and cause() tells which fired.
struct StopCondition {
  /// Wall-clock backstop (steady clock); max = none.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  const std::atomic<bool>* cancel = nullptr;
  std::uint64_t max_expansions = std::numeric_limits<std::uint64_t>::max();
  /// CPU budget: stop once `cpu_clock` has counted `cpu_deadline` (cpu_time(cpu_clock) units);
  /// max = none. `cpu_clock` names the request thread's clock, so a plugin may poll from any
  /// thread.
  std::chrono::nanoseconds cpu_deadline = std::chrono::nanoseconds::max();
  clockid_t cpu_clock = CLOCK_THREAD_CPUTIME_ID;

  bool should_stop(std::uint64_t expansions) const {
    return expansions >= max_expansions || expired();
  }
  /// A time limit passed or the cancel flag is set (the expansion budget is not consulted).
  bool expired() const { return cause() != StopCause::none; }
  /// Which limit has fired now: the cancel flag, then the CPU budget, then the wall backstop.
  StopCause cause() const {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return StopCause::cancelled;
    if (cpu_deadline != std::chrono::nanoseconds::max() && cpu_time(cpu_clock) >= cpu_deadline)
      return StopCause::cpu_budget;
    if (deadline != std::chrono::steady_clock::time_point::max() &&
        std::chrono::steady_clock::now() >= deadline)
      return StopCause::wall_backstop;
    return StopCause::none;
  }
  /// The CPU time left on the budget (max when there is none, zero when it is spent).
  std::chrono::nanoseconds cpu_left() const {
    if (cpu_deadline == std::chrono::nanoseconds::max()) return cpu_deadline;
    const auto now = cpu_time(cpu_clock);
    return now >= cpu_deadline ? std::chrono::nanoseconds::zero() : cpu_deadline - now;
  }
  /// A wall-clock limit only (tests, tools): `ms` from now.
  static StopCondition within(std::chrono::milliseconds ms) {
    StopCondition s;
    s.deadline = std::chrono::steady_clock::now() + ms;
    return s;
  }
  /// `cpu` of the calling thread's CPU time from now, with a wall-clock backstop `wall` from now
  /// (a non-positive duration means none).
  static StopCondition within_cpu(std::chrono::milliseconds cpu, std::chrono::milliseconds wall) {
    StopCondition s;
    s.cpu_clock = this_thread_cpu_clock();
    if (cpu.count() > 0) s.cpu_deadline = cpu_time(s.cpu_clock) + cpu;
    if (wall.count() > 0) s.deadline = std::chrono::steady_clock::now() + wall;
    return s;
  }
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
