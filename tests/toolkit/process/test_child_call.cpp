// toolkit/process: a call in a forked child, bounded (flipper/toolkit/process/child_call.hpp).
#include <fcntl.h>
#include <pthread.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <ctime>
#include <limits>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "flipper/toolkit/process/child_call.hpp"
#include "process_children.hpp"

namespace process = flipper::toolkit::process;
using process::ChildEnd;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

namespace {

process::ChildCall run(const std::function<void()>& body, process::ChildLimits limits = {}) {
  auto call = process::run_in_child(limits, body);
  REQUIRE(call);
  return std::move(*call);
}

nanoseconds thread_cpu() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return std::chrono::seconds(t.tv_sec) + nanoseconds(t.tv_nsec);
}

// Spins until the calling thread has used `cpu` more CPU time.
void spin(nanoseconds cpu) {
  const nanoseconds until = thread_cpu() + cpu;
  while (thread_cpu() < until) {
  }
}

// This process's children, ended (zombies) or not.
std::vector<int> my_children() {
  return flipper::testsupport::children_of(::getpid());
}

}  // namespace

TEST_CASE("a child's parts arrive in order as its answer", "[process]") {
  const auto call = run([] {
    process::send_to_parent("hel");
    process::send_to_parent("lo");
  });
  CHECK(call.end == ChildEnd::answered);
  CHECK(call.bytes == "hello");
  CHECK(run([] {}).bytes.empty());
  CHECK(run([] {}).end == ChildEnd::answered);
}

TEST_CASE("a child that exits or dies keeps what it sent before", "[process]") {
  auto call = run([] {
    process::send_to_parent("ab");
    ::_exit(7);
  });
  CHECK(call.end == ChildEnd::exited);
  CHECK(call.status == 7);
  CHECK(call.bytes == "ab");

  call = run([] {
    process::send_to_parent("cd");
    ::raise(SIGSEGV);  // the default action in the child, whatever the parent handles
  });
  CHECK(call.end == ChildEnd::signalled);
  CHECK(call.signal == SIGSEGV);
  CHECK(call.bytes == "cd");

  call = run([] { throw std::runtime_error("escaped"); });
  CHECK(call.end == ChildEnd::exited);
  CHECK(call.status == 4);
}

TEST_CASE("a child may send max_bytes and is killed at one more", "[process]") {
  process::ChildLimits limits;
  limits.max_bytes = 100'000;  // over a pipe's buffer: read as it comes
  const std::string exact(limits.max_bytes, 'x');
  auto call = run([&] { process::send_to_parent(exact); }, limits);
  CHECK(call.end == ChildEnd::answered);
  CHECK(call.bytes.size() == limits.max_bytes);
  call = run([&] { process::send_to_parent(exact + "y"); }, limits);
  CHECK(call.end == ChildEnd::too_large);
  limits.max_bytes = std::numeric_limits<std::size_t>::max();  // no bound: nothing wraps
  call = run([&] { process::send_to_parent(exact); }, limits);
  CHECK(call.end == ChildEnd::answered);
  CHECK(call.bytes.size() == exact.size());
}

// When set, every child spends 60 ms of CPU time right after the fork, before its body.
std::atomic<bool> g_slow_fork_child{false};

TEST_CASE("the CPU time of a body that answered is the body's, not the fork's", "[process]") {
  static const bool registered = ::pthread_atfork(nullptr, nullptr, [] {
                                   if (g_slow_fork_child) spin(milliseconds(60));
                                 }) == 0;
  REQUIRE(registered);
  g_slow_fork_child = true;
  const auto call = run([] { spin(milliseconds(40)); });
  g_slow_fork_child = false;
  CHECK(call.end == ChildEnd::answered);
  CHECK(call.cpu >= milliseconds(40));
  CHECK(call.cpu < milliseconds(80));  // with the 60 ms before the body: 100 ms or more
}

TEST_CASE("a child past its CPU limit ends with SIGXCPU", "[process]") {
  process::ChildLimits limits;
  limits.cpu = milliseconds(100);
  const auto call = run([] { spin(std::chrono::seconds(20)); }, limits);
  CHECK(call.end == ChildEnd::signalled);
  CHECK(call.signal == SIGXCPU);
  // 100 ms of the process's CPU time from the fork: the body had most of it, never all 20 s.
  CHECK(call.cpu >= milliseconds(50));
  CHECK(call.cpu < std::chrono::seconds(5));
}

TEST_CASE("the wall backstop and the cancel flag kill a child that does not answer", "[process]") {
  process::ChildLimits limits;
  limits.kill_by = std::chrono::steady_clock::now() + milliseconds(100);
  const auto started = std::chrono::steady_clock::now();
  auto call = run([] { ::sleep(60); }, limits);
  CHECK(call.end == ChildEnd::wall_backstop);
  CHECK(std::chrono::steady_clock::now() - started < std::chrono::seconds(30));

  std::atomic<bool> cancel{false};
  process::ChildLimits cancellable;
  cancellable.cancel = &cancel;
  std::thread setter([&] {
    std::this_thread::sleep_for(milliseconds(100));
    cancel = true;
  });
  call = run([] { ::sleep(60); }, cancellable);
  setter.join();
  CHECK(call.end == ChildEnd::cancelled);
  CHECK(std::chrono::steady_clock::now() - started < std::chrono::seconds(30));
}

TEST_CASE("a child has none of the parent's descriptors but its answer's pipe", "[process]") {
  int fds[2];
  REQUIRE(::pipe(fds) == 0);                       // below the answer's pipe, made later
  const int high = ::fcntl(fds[0], F_DUPFD, 500);  // above it
  REQUIRE(high >= 500);
  const auto call = run([&] {
    const auto closed = [](int fd) { return ::fcntl(fd, F_GETFD) == -1; };
    process::send_to_parent(std::string(closed(fds[0]) ? "closed" : "open") + " " +
                            (closed(fds[1]) ? "closed" : "open") + " " +
                            (closed(high) ? "closed" : "open"));
  });
  ::close(fds[0]);
  ::close(fds[1]);
  ::close(high);
  CHECK(call.bytes == "closed closed closed");
}

TEST_CASE("a lock read across the fork is never inherited held by a writer", "[process]") {
  std::shared_mutex mutex;
  const process::ReadAcrossFork guard(mutex);
  std::atomic<bool> writing{false};
  std::thread writer([&] {
    const std::unique_lock<std::shared_mutex> lock(mutex);
    writing = true;
    std::this_thread::sleep_for(milliseconds(200));
  });
  while (!writing) std::this_thread::yield();
  process::ChildLimits limits;
  limits.kill_by = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  const auto call = run(
      [&] {
        const std::shared_lock<std::shared_mutex> read(mutex);  // waits for ever if inherited
        process::send_to_parent("read");
      },
      limits);
  writer.join();
  CHECK(call.end == ChildEnd::answered);
  CHECK(call.bytes == "read");
}

TEST_CASE("each call reaps its own child before it returns, and no other child", "[process]") {
  // A child that answered is killed and waited for (child_call.cpp reap): nothing is left to
  // pile up. Not waiting (leaving the exits to later calls) was measured and refused:
  // docs/plugins-untrusted.md §6 "Cost".
  const pid_t other = ::fork();  // a child of this process that no call may reap
  if (other == 0) ::_exit(7);
  REQUIRE(other > 0);
  for (int i = 0; i < 200; ++i) {
    REQUIRE(run([] {}).end == ChildEnd::answered);
    REQUIRE(my_children() == std::vector<int>{other});
  }
  process::ChildLimits limits;
  limits.kill_by = std::chrono::steady_clock::now() + milliseconds(50);  // killed, then reaped
  REQUIRE(run([] { spin(std::chrono::seconds(20)); }, limits).end == ChildEnd::wall_backstop);
  CHECK(my_children() == std::vector<int>{other});
  CHECK(run([] { ::raise(SIGKILL); }).end == ChildEnd::signalled);  // died by itself
  CHECK(my_children() == std::vector<int>{other});
  int status = 0;
  REQUIRE(::waitpid(other, &status, 0) == other);  // still this test's to reap
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 7);
}

TEST_CASE("send_to_parent outside a child is refused", "[process]") {
  CHECK_THROWS_AS(process::send_to_parent("x"), std::logic_error);
}
