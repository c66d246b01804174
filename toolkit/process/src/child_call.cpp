// A bounded call in a forked child process (child_call.hpp).
#include "flipper/toolkit/process/child_call.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace flipper::toolkit::process {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;

// --- locks held shared across each fork (ReadAcrossFork) ----------------------------------

std::mutex g_fork_reads_mutex;
std::vector<std::shared_mutex*>& fork_reads() {
  static auto* const list = new std::vector<std::shared_mutex*>();  // NOLINT: never destroyed
  return *list;
}

pid_t fork_holding_reads() {
  const std::lock_guard<std::mutex> registry(g_fork_reads_mutex);
  for (std::shared_mutex* m : fork_reads()) m->lock_shared();
  const pid_t pid = ::fork();
  if (pid != 0)
    for (std::shared_mutex* m : fork_reads()) m->unlock_shared();
  return pid;  // the child keeps them shared: it only reads, then _exits
}

nanoseconds cpu_of(const rusage& ru) {
  return std::chrono::seconds(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         std::chrono::microseconds(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

nanoseconds duration_of(const timespec& t) {
  return std::chrono::seconds(t.tv_sec) + nanoseconds(t.tv_nsec);
}

nanoseconds process_cpu_now() {
  timespec now{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return duration_of(now);
}

// In the child, before the body (child_call.hpp run_in_child), and a CPU-time limit that ends a
// child running past it (SIGXCPU).
void prepare_child(int answer_fd, nanoseconds cpu_limit) {
  for (const int s : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGXCPU, SIGTERM, SIGINT, SIGHUP})
    ::signal(s, SIG_DFL);      // the parent's handlers write to the parent's files
  ::signal(SIGPIPE, SIG_IGN);  // a parent gone: the write fails, the child exits
  sigset_t none;
  sigemptyset(&none);
  ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (answer_fd > 3) ::close_range(3, static_cast<unsigned>(answer_fd) - 1, 0);
  ::close_range(static_cast<unsigned>(answer_fd) + 1, ~0u, 0);
  if (cpu_limit == nanoseconds::max()) return;
  sigevent event{};
  event.sigev_notify = SIGEV_SIGNAL;
  event.sigev_signo = SIGXCPU;
  timer_t timer{};
  if (::timer_create(CLOCK_PROCESS_CPUTIME_ID, &event, &timer) != 0) return;
  itimerspec when{};
  const auto s = std::chrono::duration_cast<std::chrono::seconds>(cpu_limit);
  when.it_value.tv_sec = static_cast<time_t>(s.count());
  when.it_value.tv_nsec = static_cast<long>((cpu_limit - s).count());
  if (when.it_value.tv_sec == 0 && when.it_value.tv_nsec == 0) when.it_value.tv_nsec = 1;
  ::timer_settime(timer, 0, &when, nullptr);
}

void write_all(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) ::_exit(3);  // the parent stopped reading: nothing to tell it
    done += static_cast<std::size_t>(n);
  }
}

// The child's first bytes: its process CPU clock just before the body (nanoseconds, this
// machine's byte order), written before the body runs, so the body cannot change them.
constexpr std::size_t kStartBytes = sizeof(std::int64_t);

nanoseconds start_of(std::string_view bytes) {
  std::int64_t v = 0;
  std::memcpy(&v, bytes.data(), kStartBytes);
  return nanoseconds(std::max<std::int64_t>(v, 0));
}

int g_answer_fd = -1;  // in a child: its answer's pipe

[[noreturn]] void run_child(int answer_fd, nanoseconds cpu_limit,
                            const std::function<void()>& body) {
  prepare_child(answer_fd, cpu_limit);
  const std::int64_t start = process_cpu_now().count();
  write_all(answer_fd, {reinterpret_cast<const char*>(&start), kStartBytes});  // NOLINT: bytes
  g_answer_fd = answer_fd;
  try {
    body();
  } catch (...) {
    ::_exit(4);
  }
  // Answered: stopped here, the parent reads this process's CPU clock and kills it, so that its
  // exit (unmapping a copy of the parent's address space) is not counted as the body's work.
  ::close(answer_fd);
  ::raise(SIGSTOP);
  ::_exit(0);
}

// Reaps a child that ended or is being killed or, `answered`, the child that closed the pipe
// after its answer: having answered it stops itself (run_child), and the body's CPU time is then
// its process clock less `started` (its first bytes, when they came); it is killed and reaped.
// A child that ended is counted its CPU time by wait4 less `started`.
void reap(pid_t pid, std::optional<nanoseconds> started, ChildCall& call, bool answered = false) {
  int raw = 0;
  rusage ru{};
  pid_t got;
  do got = ::wait4(pid, &raw, answered ? WUNTRACED : 0, &ru);
  while (got < 0 && errno == EINTR);
  if (got != pid) return;
  if (WIFSTOPPED(raw)) {
    clockid_t clock{};
    timespec now{};
    const bool read =
        started && ::clock_getcpuclockid(pid, &clock) == 0 && ::clock_gettime(clock, &now) == 0;
    ::kill(pid, SIGKILL);
    do got = ::wait4(pid, &raw, 0, &ru);
    while (got < 0 && errno == EINTR);
    call.cpu =
        read ? duration_of(now) - *started : cpu_of(ru);  // no clock to read: everything it used
    return;
  }
  call.cpu = std::max(cpu_of(ru) - started.value_or(nanoseconds::zero()), nanoseconds::zero());
  if (!answered) return;  // killed by the parent: how it ended is already said
  if (WIFSIGNALED(raw)) {
    call.end = ChildEnd::signalled;
    call.signal = WTERMSIG(raw);
  } else if (WIFEXITED(raw) && WEXITSTATUS(raw) != 0) {
    call.end = ChildEnd::exited;
    call.status = WEXITSTATUS(raw);
  }
}

// Reads the child's answer as it comes (it may be larger than a pipe holds) until it closes its
// end, or a limit ends the wait: the child is then killed and `call` says which limit.
void read_answer(pid_t pid, int in, const ChildLimits& limits, ChildCall& call,
                 std::string& bytes) {
  const auto started = [&bytes]() -> std::optional<nanoseconds> {
    return bytes.size() < kStartBytes ? std::nullopt : std::optional(start_of(bytes));
  };
  const auto kill = [&](ChildEnd end) {
    ::kill(pid, SIGKILL);
    call.end = end;
    reap(pid, started(), call);
  };
  char buffer[65536];
  for (;;) {
    int timeout_ms = limits.cancel != nullptr ? 50 : -1;
    if (limits.kill_by != std::chrono::steady_clock::time_point::max()) {
      const auto left = std::chrono::duration_cast<milliseconds>(limits.kill_by -
                                                                 std::chrono::steady_clock::now());
      const int ms = static_cast<int>(std::clamp<std::int64_t>(left.count() + 1, 0, 60000));
      timeout_ms = timeout_ms < 0 ? ms : std::min(timeout_ms, ms);
    }
    pollfd p{in, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_ms);
    if (ready < 0 && errno == EINTR) continue;
    if (limits.cancel != nullptr && limits.cancel->load(std::memory_order_relaxed))
      return kill(ChildEnd::cancelled);
    if (ready == 0) {
      if (std::chrono::steady_clock::now() < limits.kill_by) continue;
      return kill(ChildEnd::wall_backstop);
    }
    const ssize_t n = ::read(in, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of the answer (or an error reading it: how the child ended says)
    const std::size_t sent = bytes.size() + static_cast<std::size_t>(n);
    if (sent > kStartBytes && sent - kStartBytes > limits.max_bytes)  // no wrap at SIZE_MAX
      return kill(ChildEnd::too_large);
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  reap(pid, started(), call, true);
}

}  // namespace

std::optional<ChildCall> run_in_child(const ChildLimits& limits,
                                      const std::function<void()>& body) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return std::nullopt;
  const pid_t pid = fork_holding_reads();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return std::nullopt;
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_child(fds[1], limits.cpu, body);
  }
  ::close(fds[1]);
  ChildCall call;
  std::string bytes;
  read_answer(pid, fds[0], limits, call, bytes);
  ::close(fds[0]);
  bytes.erase(0, std::min(bytes.size(), kStartBytes));  // the clock before the body
  call.bytes = std::move(bytes);
  return call;
}

void send_to_parent(std::string_view bytes) {
  if (g_answer_fd < 0) throw std::logic_error("send_to_parent outside a child of run_in_child");
  write_all(g_answer_fd, bytes);
}

ReadAcrossFork::ReadAcrossFork(std::shared_mutex& mutex) : mutex_(&mutex) {
  const std::lock_guard<std::mutex> lock(g_fork_reads_mutex);
  fork_reads().push_back(mutex_);
}

ReadAcrossFork::~ReadAcrossFork() {
  const std::lock_guard<std::mutex> lock(g_fork_reads_mutex);
  auto& list = fork_reads();
  list.erase(std::remove(list.begin(), list.end(), mutex_), list.end());
}

}  // namespace flipper::toolkit::process
