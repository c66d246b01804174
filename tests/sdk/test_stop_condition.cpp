// StopCondition's time limits (docs/planners.md §2): the CPU budget counts the request thread's
// CPU time, readable from any thread; the wall-clock deadline is the backstop; cause() names the
// limit that fired; StoppedError carries it.
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/stop.hpp"

namespace sdk = flipper::sdk;
using std::chrono::milliseconds;

namespace {

// Spins until this thread's CPU clock has counted `d` more.
void burn(std::chrono::nanoseconds d) {
  const auto until = sdk::cpu_time() + d;
  volatile std::uint64_t spins = 0;
  while (sdk::cpu_time() < until) spins = spins + 1;
}

}  // namespace

TEST_CASE("the CPU budget fires after the thread used it, not after time passed") {
  const auto stop = sdk::StopCondition::within_cpu(milliseconds(50), milliseconds(0));
  CHECK(stop.deadline == std::chrono::steady_clock::time_point::max());  // 0: no backstop
  CHECK(stop.cause() == sdk::StopCause::none);
  // Time passing without CPU (the thread sleeps, as a starved thread waits) does not count.
  std::this_thread::sleep_for(milliseconds(80));
  CHECK(stop.cause() == sdk::StopCause::none);
  CHECK_FALSE(stop.should_stop(0));
  CHECK(stop.cpu_left() > milliseconds(0));
  // CPU used does: the boundary, read on the same clock.
  burn(milliseconds(60));
  CHECK(stop.cause() == sdk::StopCause::cpu_budget);
  CHECK(stop.expired());
  CHECK(stop.should_stop(0));
  CHECK(stop.cpu_left() == std::chrono::nanoseconds::zero());
}

TEST_CASE("the CPU budget names the request thread's clock, read from another thread") {
  const auto stop = sdk::StopCondition::within_cpu(milliseconds(30), milliseconds(0));
  // Another thread burning its own CPU does not spend the request thread's budget ...
  std::thread other([] { burn(milliseconds(60)); });
  other.join();
  CHECK(stop.cause() == sdk::StopCause::none);
  // ... and the request thread's spending is seen from another thread.
  burn(milliseconds(40));
  sdk::StopCause seen = sdk::StopCause::none;
  std::thread reader([&] { seen = stop.cause(); });
  reader.join();
  CHECK(seen == sdk::StopCause::cpu_budget);
}

TEST_CASE("cause(): the cancel flag, then the CPU budget, then the wall backstop") {
  sdk::StopCondition stop;
  CHECK(stop.cause() == sdk::StopCause::none);
  stop.deadline = std::chrono::steady_clock::now();
  CHECK(stop.cause() == sdk::StopCause::wall_backstop);
  stop.cpu_clock = sdk::this_thread_cpu_clock();
  stop.cpu_deadline = sdk::cpu_time(stop.cpu_clock);
  CHECK(stop.cause() == sdk::StopCause::cpu_budget);
  std::atomic<bool> cancel{true};
  stop.cancel = &cancel;
  CHECK(stop.cause() == sdk::StopCause::cancelled);
  // The expansion budget is work: should_stop at N, not at N - 1; expired() ignores it.
  sdk::StopCondition work;
  work.max_expansions = 10;
  CHECK_FALSE(work.should_stop(9));
  CHECK(work.should_stop(10));
  CHECK_FALSE(work.expired());
  CHECK(std::string(sdk::to_string(sdk::StopCause::cpu_budget)) == "cpu_budget");
  CHECK(std::string(sdk::to_string(sdk::StopCause::wall_backstop)) == "wall_backstop");
}

TEST_CASE("StoppedError is deadline_exceeded with its cause") {
  const sdk::StoppedError e(sdk::StopCause::wall_backstop, "too long");
  CHECK(e.code() == "deadline_exceeded");
  CHECK(sdk::stop_cause_of(e) == sdk::StopCause::wall_backstop);
  CHECK(sdk::stop_cause_of(sdk::Error("deadline_exceeded", "x")) == sdk::StopCause::none);
}

TEST_CASE("a poll reads the CPU clock only when the last reading cannot prove the budget unspent") {
  const auto& last = sdk::last_cpu_reading();
  // Far from the budget's end: the reading taken at the start answers the polls (none is taken).
  const auto stop = sdk::StopCondition::within_cpu(milliseconds(500), milliseconds(0));
  REQUIRE(last.clock == stop.cpu_clock);
  const auto taken = last.at;
  CHECK(stop.cause() == sdk::StopCause::none);
  CHECK_FALSE(stop.expired());
  CHECK(last.at == taken);
  // Near it (within 1 ms, or twice the time passed since that reading): the clock is read.
  sdk::StopCondition near = stop;
  near.cpu_deadline = last.cpu + milliseconds(1);
  CHECK(near.cause() == sdk::StopCause::none);
  CHECK(last.at > taken);
  // The CPU used since the last reading counts, though no poll read the clock meanwhile: the
  // bound grows with the time that passed, so a budget spent is seen as spent.
  static_cast<void>(sdk::read_cpu_clock(stop.cpu_clock));
  burn(milliseconds(5));
  sdk::StopCondition spent = stop;
  spent.cpu_deadline = sdk::cpu_time(stop.cpu_clock);
  CHECK(spent.cause() == sdk::StopCause::cpu_budget);
  CHECK(spent.cpu_left() == std::chrono::nanoseconds::zero());
}

TEST_CASE("a reading of one clock proves nothing about another") {
  static_cast<void>(sdk::read_cpu_clock(CLOCK_THREAD_CPUTIME_ID));
  // The process's clock counts every thread's CPU, faster than time passes: never remembered,
  // always read.
  static_cast<void>(sdk::read_cpu_clock(CLOCK_PROCESS_CPUTIME_ID));
  CHECK(sdk::last_cpu_reading().clock == CLOCK_THREAD_CPUTIME_ID);
  sdk::StopCondition process;
  process.cpu_clock = CLOCK_PROCESS_CPUTIME_ID;
  process.cpu_deadline = sdk::cpu_time(CLOCK_PROCESS_CPUTIME_ID);
  CHECK(process.cause() == sdk::StopCause::cpu_budget);
  // This thread's clock under another name is read too (and remembered under that name).
  sdk::StopCondition other;
  other.cpu_clock = sdk::this_thread_cpu_clock();
  other.cpu_deadline = sdk::cpu_time(other.cpu_clock);
  CHECK(other.cause() == sdk::StopCause::cpu_budget);
  CHECK(sdk::last_cpu_reading().clock == other.cpu_clock);
}
