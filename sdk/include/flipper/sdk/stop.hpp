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

/// The last reading of a thread's CPU clock taken on this thread by read_cpu_clock, with the
/// steady clock's time taken just before it (`cpu` negative: none yet).
struct CpuClockReading {
  clockid_t clock = CLOCK_THREAD_CPUTIME_ID;
  std::chrono::nanoseconds cpu{-1};
  std::chrono::steady_clock::time_point at{};
};
inline CpuClockReading& last_cpu_reading() {
  static thread_local CpuClockReading reading;
  return reading;
}
/// A clock of one thread (CLOCK_THREAD_CPUTIME_ID, or pthread_getcpuclockid's, whose bit 2 says
/// "thread" on Linux): it counts at most the real time that passes, unlike a process's clock.
inline bool counts_one_thread(clockid_t clock) {
  return clock == CLOCK_THREAD_CPUTIME_ID || (clock < 0 && (clock & 4) != 0);
}

/// cpu_time(clock), remembered on the calling thread (with `now`, the steady clock's time taken
/// before the read) so that cpu_clock_before() can answer later polls without reading the clock.
inline std::chrono::nanoseconds read_cpu_clock(
    clockid_t clock, std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now()) {
  const auto cpu = cpu_time(clock);
  if (cpu != std::chrono::nanoseconds::max() && counts_one_thread(clock))
    last_cpu_reading() = CpuClockReading{clock, cpu, now};
  return cpu;
}

/// Whether `clock` is still below `deadline` at steady time `now`: exactly what a reading of the
/// clock at `now` says, with the reading skipped when the calling thread's last reading of the
/// same clock already proves it (docs/planners.md §2). A thread runs for at most the real time
/// that passes, so its clock is at most that reading plus the steady time since; the bound
/// doubles that time and adds 1 ms, far more than any difference in the two clocks' rates. Only
/// when the bound reaches the deadline is the clock read (a system call).
inline bool cpu_clock_before(clockid_t clock, std::chrono::nanoseconds deadline,
                             std::chrono::steady_clock::time_point now) {
  const CpuClockReading& last = last_cpu_reading();
  if (last.clock == clock && last.cpu.count() >= 0 && now >= last.at) {
    const auto since = std::chrono::duration_cast<std::chrono::nanoseconds>(now - last.at);
    if (last.cpu + 2 * since + std::chrono::milliseconds(1) < deadline) return true;
  }
  return read_cpu_clock(clock, now) < deadline;
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
  /// The CPU clock is read only when the last reading on this thread cannot prove the budget
  /// unspent (cpu_clock_before): a poll costs a system call only near the budget's end.
  StopCause cause() const {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return StopCause::cancelled;
    const bool cpu = cpu_deadline != std::chrono::nanoseconds::max();
    const bool wall = deadline != std::chrono::steady_clock::time_point::max();
    if (!cpu && !wall) return StopCause::none;
    const auto now = std::chrono::steady_clock::now();
    if (cpu && !cpu_clock_before(cpu_clock, cpu_deadline, now)) return StopCause::cpu_budget;
    if (wall && now >= deadline) return StopCause::wall_backstop;
    return StopCause::none;
  }
  /// The CPU time left on the budget (max when there is none, zero when it is spent).
  std::chrono::nanoseconds cpu_left() const {
    if (cpu_deadline == std::chrono::nanoseconds::max()) return cpu_deadline;
    const auto now = read_cpu_clock(cpu_clock);
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
    const auto now = std::chrono::steady_clock::now();
    if (cpu.count() > 0) s.cpu_deadline = read_cpu_clock(s.cpu_clock, now) + cpu;
    if (wall.count() > 0) s.deadline = now + wall;
    return s;
  }
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
