// Plugin calls in a forked child process (isolation.hpp, docs/plugins-untrusted.md §6).
#include "flipper/kernel/isolation.hpp"

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
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {
namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;

// --- CPU charges: budgets attached per thread --------------------------------------------

struct Attached {
  sdk::StopCondition* budget;
  pthread_t owner;
};
std::mutex g_charges_mutex;
// Never destroyed: a static session's CpuCharge may detach at exit after a static list's end.
std::vector<Attached>& charges() {
  static auto* const list = new std::vector<Attached>();  // NOLINT(cppcoreguidelines-owning-memory)
  return *list;
}

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

// The envelope a child sends: 'A' + answer bytes, or 'E' + sdk::host::CallFailure's bytes.

std::string signal_text(int signal) {
  const char* abbrev = sigabbrev_np(signal);
  return abbrev != nullptr ? std::string("SIG") + abbrev : "signal " + std::to_string(signal);
}

nanoseconds cpu_of(const rusage& ru) {
  return std::chrono::seconds(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         std::chrono::microseconds(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

// In the child, before the call: the default action for the signals a crash raises (the
// parent's handlers write to the parent's files), no signal blocked (the request thread may
// block some), dead with the thread that forked it, none of the parent's descriptors but the
// answer's pipe, and a CPU-time limit that ends a call running past its budget (SIGXCPU).
void prepare_child(int answer_fd, nanoseconds cpu_limit) {
  for (const int s : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGXCPU, SIGTERM, SIGINT, SIGHUP})
    ::signal(s, SIG_DFL);
  ::signal(SIGPIPE, SIG_IGN);  // a parent gone: the write fails, the child exits
  sigset_t none;
  sigemptyset(&none);
  ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (answer_fd > 3) ::close_range(3, static_cast<unsigned>(answer_fd) - 1, 0);
  ::close_range(static_cast<unsigned>(answer_fd) + 1, ~0u, 0);
  if (cpu_limit != nanoseconds::max()) {
    sigevent event{};
    event.sigev_notify = SIGEV_SIGNAL;
    event.sigev_signo = SIGXCPU;
    timer_t timer{};
    if (::timer_create(CLOCK_PROCESS_CPUTIME_ID, &event, &timer) == 0) {
      itimerspec when{};
      const auto s = std::chrono::duration_cast<std::chrono::seconds>(cpu_limit);
      when.it_value.tv_sec = static_cast<time_t>(s.count());
      when.it_value.tv_nsec = static_cast<long>((cpu_limit - s).count());
      if (when.it_value.tv_sec == 0 && when.it_value.tv_nsec == 0) when.it_value.tv_nsec = 1;
      ::timer_settime(timer, 0, &when, nullptr);
    }
  }
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

// The child's first bytes: its process CPU clock just before the call (nanoseconds, this
// machine's byte order), written by this code before the call, so the call cannot change it.
constexpr std::size_t kStartBytes = sizeof(std::int64_t);

std::string start_bytes(nanoseconds cpu) {
  const std::int64_t v = cpu.count();
  return {reinterpret_cast<const char*>(&v), kStartBytes};  // NOLINT: the value's bytes
}

nanoseconds start_of(std::string_view bytes) {
  std::int64_t v = 0;
  std::memcpy(&v, bytes.data(), kStartBytes);
  return nanoseconds(std::max<std::int64_t>(v, 0));
}

// In a child: its answer's pipe, and whether send_part has begun the answer ('A' sent).
int g_part_fd = -1;
bool g_parts_sent = false;

[[noreturn]] void run_child(const PluginId& plugin, std::string_view op, int answer_fd,
                            const sdk::StopCondition& parent_stop, nanoseconds cpu_left,
                            const std::function<std::string(const sdk::StopCondition&)>& work) {
  prepare_child(answer_fd,
                cpu_left == nanoseconds::max() ? cpu_left : cpu_left + detail::kCpuGrace);
  // What the fork cost this process so far (its copy-on-write faults) is the isolation's.
  write_all(answer_fd, start_bytes(sdk::cpu_time(CLOCK_PROCESS_CPUTIME_ID)));
  sdk::StopCondition stop;  // the parent's limits, its CPU budget on this process's one thread
  stop.deadline = parent_stop.deadline;
  stop.max_expansions = parent_stop.max_expansions;
  stop.cpu_clock = CLOCK_THREAD_CPUTIME_ID;
  if (cpu_left != nanoseconds::max()) stop.cpu_deadline = sdk::cpu_time() + cpu_left;
  g_part_fd = answer_fd;
  g_parts_sent = false;  // this child's own answer (a child may fork one of its own)
  std::string out;
  try {
    std::string answer = work(stop);
    out.reserve(answer.size() + 1);
    if (!g_parts_sent) out.push_back('A');
    out += answer;
  } catch (...) {
    std::optional<std::string> failure = detail::failure_bytes(plugin, op);
    if (!failure || g_parts_sent) ::_exit(4);  // a failure after parts: not one answer
    out = "E" + *failure;
  }
  write_all(answer_fd, out);
  // Answered: stopped here, the parent reads this process's CPU clock and kills it, so that its
  // exit (unmapping a copy of the parent's address space) is not charged as the call's work.
  ::close(answer_fd);
  ::raise(SIGSTOP);
  ::_exit(0);
}

// The parent's side of a child that ended or was killed: reaped, its CPU time charged.
struct Reaped {
  int signal = 0;  // the signal that ended it (0: it exited)
  int status = 0;  // its exit status when it exited
};
// Reaps a child that ended or is being killed, or, `answered`, the child that closed the pipe
// after its answer: having answered it stops itself (run_child), and the call's CPU time is then
// its process clock less `started` (its first bytes, when they came); it is killed and reaped
// uncharged, so that its exit is not charged as the call's work. A child that ended is charged
// its CPU time by wait4 less `started`: what the fork cost it before the call is not the call's.
Reaped reap(pid_t pid, std::optional<nanoseconds> started, bool answered = false) {
  int raw = 0;
  rusage ru{};
  pid_t got;
  do got = ::wait4(pid, &raw, answered ? WUNTRACED : 0, &ru);
  while (got < 0 && errno == EINTR);
  Reaped r;
  if (got != pid) return r;
  if (WIFSTOPPED(raw)) {
    clockid_t clock{};
    timespec now{};
    const bool read =
        started && ::clock_getcpuclockid(pid, &clock) == 0 && ::clock_gettime(clock, &now) == 0;
    ::kill(pid, SIGKILL);
    do got = ::wait4(pid, &raw, 0, &ru);
    while (got < 0 && errno == EINTR);
    charge_cpu(read ? std::chrono::seconds(now.tv_sec) + nanoseconds(now.tv_nsec) - *started
                    : cpu_of(ru));  // no clock to read: everything it used
    return r;
  }
  charge_cpu(cpu_of(ru) - started.value_or(nanoseconds::zero()));
  if (WIFSIGNALED(raw)) r.signal = WTERMSIG(raw);
  if (WIFEXITED(raw)) r.status = WEXITSTATUS(raw);
  return r;
}

[[noreturn]] void crashed(const PluginId& plugin, std::string_view op, const std::string& what) {
  throw sdk::Error(kPluginCrashed, plugin.label() + ": " + std::string(op) + ": " + what);
}

}  // namespace

void CpuCharge::attach(sdk::StopCondition& budget) {
  const std::lock_guard<std::mutex> lock(g_charges_mutex);
  auto& list = charges();
  if (budget_ != nullptr)
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const Attached& a) { return a.budget == budget_; }),
               list.end());
  budget_ = &budget;
  list.push_back(Attached{budget_, ::pthread_self()});
}

void CpuCharge::detach() {
  if (budget_ == nullptr) return;
  const std::lock_guard<std::mutex> lock(g_charges_mutex);
  auto& list = charges();
  list.erase(std::remove_if(list.begin(), list.end(),
                            [&](const Attached& a) { return a.budget == budget_; }),
             list.end());
  budget_ = nullptr;
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

namespace {

// Moves the CPU deadline of every budget attached on the calling thread by `by`: earlier for a
// charge (negative), later for a refund; an unlimited budget stays unlimited.
void move_deadlines(nanoseconds by) {
  const std::lock_guard<std::mutex> lock(g_charges_mutex);
  const pthread_t self = ::pthread_self();
  constexpr nanoseconds kLatest = nanoseconds::max() - nanoseconds(1);
  for (const Attached& a : charges()) {
    if (::pthread_equal(a.owner, self) == 0) continue;
    nanoseconds& deadline = a.budget->cpu_deadline;
    if (deadline == nanoseconds::max()) continue;
    if (by < nanoseconds::zero())
      deadline = deadline > -by ? deadline + by : nanoseconds::zero();
    else
      deadline = deadline < kLatest - by ? deadline + by : kLatest;
  }
}

// While alive: the calling thread's CPU time until it ends goes back to its budgets, as time
// spent isolating a call (forking, waiting), which a call in process does not cost.
struct RefundThreadCpu {
  nanoseconds start = sdk::cpu_time();
  ~RefundThreadCpu() { move_deadlines(std::max(sdk::cpu_time() - start, nanoseconds::zero())); }
};

}  // namespace

void charge_cpu(nanoseconds cpu) {
  if (cpu > nanoseconds::zero()) move_deadlines(-cpu);
}

namespace {

std::optional<std::string> call_in_child_reading(
    const PluginId& plugin, std::string_view op, const sdk::StopCondition& stop,
    const std::function<std::string(const sdk::StopCondition&)>& work, std::string& bytes) {
  // The budgets count the call's work, as in process (docs/plugins-untrusted.md §6): not this
  // thread's fork and waits, nor what the child spends before the call and on its exit.
  const RefundThreadCpu isolating;
  const nanoseconds cpu_left = stop.cpu_left();
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
    run_child(plugin, op, fds[1], stop, cpu_left, work);
  }
  ::close(fds[1]);
  const int in = fds[0];
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{in};

  // The answer, read as it comes (it may be larger than a pipe holds), until the child closes
  // its end. A wall backstop (with the grace a planner gets to notice it) and the cancel flag
  // end the wait; a child that sends more than detail::kMaxAnswerBytes is ended too.
  const auto kill_by =
      stop.deadline == std::chrono::steady_clock::time_point::max()
          ? stop.deadline
          : stop.deadline + std::chrono::duration_cast<milliseconds>(detail::kCpuGrace);
  const auto started_so_far = [&bytes]() -> std::optional<nanoseconds> {
    return bytes.size() < kStartBytes ? std::nullopt : std::optional(start_of(bytes));
  };
  char buffer[65536];
  for (;;) {
    int timeout_ms = -1;
    if (stop.cancel != nullptr) timeout_ms = 50;
    if (kill_by != std::chrono::steady_clock::time_point::max()) {
      const auto left =
          std::chrono::duration_cast<milliseconds>(kill_by - std::chrono::steady_clock::now());
      const int ms = static_cast<int>(std::clamp<std::int64_t>(left.count() + 1, 0, 60000));
      timeout_ms = timeout_ms < 0 ? ms : std::min(timeout_ms, ms);
    }
    pollfd p{in, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_ms);
    if (ready < 0 && errno == EINTR) continue;
    if (stop.cancel != nullptr && stop.cancel->load(std::memory_order_relaxed)) {
      ::kill(pid, SIGKILL);
      reap(pid, started_so_far());
      throw sdk::StoppedError(sdk::StopCause::cancelled, "deadline exceeded: cancelled");
    }
    if (ready == 0) {
      if (std::chrono::steady_clock::now() < kill_by) continue;
      ::kill(pid, SIGKILL);
      reap(pid, started_so_far());
      throw sdk::StoppedError(sdk::StopCause::wall_backstop,
                              "deadline exceeded: " + plugin.label() + ": " + std::string(op) +
                                  ": still running past the wall-clock backstop, its process "
                                  "killed (stopped: wall_backstop)");
    }
    const ssize_t n = ::read(in, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of the answer (or an error reading it: judged below)
    if (bytes.size() + static_cast<std::size_t>(n) > detail::kMaxAnswerBytes) {
      ::kill(pid, SIGKILL);
      reap(pid, started_so_far());
      crashed(plugin, op,
              "its answer is larger than " + std::to_string(detail::kMaxAnswerBytes) +
                  " bytes, its process killed");
    }
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  const Reaped r = reap(pid, started_so_far(), true);
  if (r.signal == SIGXCPU && cpu_left != nanoseconds::max())
    crashed(plugin, op,
            "SIGXCPU (still running " + std::to_string(detail::kCpuGrace.count()) +
                " ms of CPU time after its budget was spent)");
  if (r.signal != 0) crashed(plugin, op, signal_text(r.signal));
  std::string_view in_view(bytes);
  in_view.remove_prefix(std::min(bytes.size(), kStartBytes));  // the clock before the call
  if (r.status != 0 || in_view.empty())
    crashed(plugin, op,
            "its process exited with status " + std::to_string(r.status) + " and no answer");
  const char tag = in_view.front();
  in_view.remove_prefix(1);
  if (tag == 'A') return std::string(in_view);
  if (tag != 'E') crashed(plugin, op, "its process sent a malformed answer");
  detail::throw_failure(plugin, op, in_view);
}

}  // namespace

namespace detail {

void send_part(std::string_view bytes) {
  if (g_part_fd < 0) throw std::logic_error("send_part outside an isolated call's child");
  if (!g_parts_sent) {
    write_all(g_part_fd, "A");
    g_parts_sent = true;
  }
  write_all(g_part_fd, bytes);
}

std::optional<std::string> call_in_child(
    const PluginId& plugin, std::string_view op, const sdk::StopCondition& stop,
    const std::function<std::string(const sdk::StopCondition&)>& work, std::string* received) {
  std::string bytes;
  try {
    return call_in_child_reading(plugin, op, stop, work, bytes);
  } catch (...) {
    if (received != nullptr)
      *received = bytes.size() > kStartBytes ? bytes.substr(kStartBytes) : std::string();
    throw;
  }
}

std::optional<std::string> failure_bytes(const PluginId& plugin, std::string_view op) {
  try {
    rethrow_plugin_failure(plugin, op);
  } catch (const sdk::Error& e) {
    return sdk::host::to_bytes(sdk::host::CallFailure{
        static_cast<std::uint64_t>(sdk::stop_cause_of(e)), e.code(), e.what()});
  } catch (...) {
  }
  return std::nullopt;
}

void throw_failure(const PluginId& plugin, std::string_view op, std::string_view bytes) {
  const auto failure = sdk::host::call_failure_of(bytes);
  if (!failure || failure->cause > static_cast<std::uint64_t>(sdk::StopCause::wall_backstop))
    crashed(plugin, op, "its process sent a malformed answer");
  if (failure->cause != 0)
    throw sdk::StoppedError(static_cast<sdk::StopCause>(failure->cause), failure->message);
  throw sdk::Error(failure->code, failure->message);
}

}  // namespace detail
}  // namespace flipper::kernel
