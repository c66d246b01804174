// Plugin calls in a forked child process (isolation.hpp, docs/plugins-untrusted.md §6), on the
// toolkit's bounded child call (flipper/toolkit/process/child_call.hpp).
#include "flipper/kernel/isolation.hpp"

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/process/child_call.hpp"

namespace flipper::kernel {
namespace {

using std::chrono::nanoseconds;
namespace process = toolkit::process;

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
  ~RefundThreadCpu() { refund_cpu(sdk::cpu_time() - start); }
};

std::string signal_text(int signal) {
  const char* abbrev = sigabbrev_np(signal);
  return abbrev != nullptr ? std::string("SIG") + abbrev : "signal " + std::to_string(signal);
}

[[noreturn]] void crashed(const PluginId& plugin, std::string_view op, const std::string& what) {
  throw sdk::Error(kPluginCrashed, plugin.label() + ": " + std::string(op) + ": " + what);
}

// In a child: whether send_part has begun the answer (its 'A' sent).
bool g_parts_sent = false;

// The child's body: the call with the parent's limits, its CPU budget on the child's one thread,
// answered as 'A' + the answer's bytes or 'E' + sdk::host::CallFailure's bytes.
void answer_in_child(const PluginId& plugin, std::string_view op,
                     const sdk::StopCondition& parent_stop, nanoseconds cpu_left,
                     const std::function<std::string(const sdk::StopCondition&)>& work) {
  sdk::StopCondition stop;
  stop.deadline = parent_stop.deadline;
  stop.max_expansions = parent_stop.max_expansions;
  stop.cpu_clock = CLOCK_THREAD_CPUTIME_ID;
  if (cpu_left != nanoseconds::max()) stop.cpu_deadline = sdk::cpu_time() + cpu_left;
  g_parts_sent = false;  // this child's own answer (a child may fork one of its own)
  std::string answer;
  try {
    answer = work(stop);
  } catch (...) {
    std::optional<std::string> failure = detail::failure_bytes(plugin, op);
    if (!failure || g_parts_sent) ::_exit(4);  // a failure after parts: not one answer
    process::send_to_parent("E" + *failure);
    return;
  }
  if (!g_parts_sent) process::send_to_parent("A");
  process::send_to_parent(answer);  // sent as it is: an answer may be large
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

namespace {
thread_local nanoseconds t_charged{0};  // charged_cpu
}  // namespace

void charge_cpu(nanoseconds cpu) {
  if (cpu <= nanoseconds::zero()) return;
  move_deadlines(-cpu);
  t_charged += cpu;
}

void refund_cpu(nanoseconds cpu) {
  if (cpu <= nanoseconds::zero()) return;
  move_deadlines(cpu);
  t_charged -= cpu;
}

nanoseconds charged_cpu() {
  return t_charged;
}

namespace detail {

void send_part(std::string_view bytes) {
  if (!g_parts_sent) {
    process::send_to_parent("A");
    g_parts_sent = true;
  }
  process::send_to_parent(bytes);
}

std::optional<std::string> call_in_child(
    const PluginId& plugin, std::string_view op, const sdk::StopCondition& stop,
    const std::function<std::string(const sdk::StopCondition&)>& work, std::string* received,
    bool charge) {
  // The budgets count the call's work, as in process (docs/plugins-untrusted.md §6): not this
  // thread's fork and waits, nor what the child spends before the call and on its exit.
  const RefundThreadCpu isolating;
  const nanoseconds cpu_left = stop.cpu_left();
  process::ChildLimits limits;
  if (cpu_left != nanoseconds::max()) limits.cpu = cpu_left + kCpuGrace;
  // The wall backstop, with the grace a planner gets to notice it.
  if (stop.deadline != std::chrono::steady_clock::time_point::max())
    limits.kill_by = stop.deadline + kCpuGrace;
  limits.cancel = stop.cancel;
  limits.max_bytes = kMaxAnswerBytes;
  std::optional<process::ChildCall> child =
      process::run_in_child(limits, [&] { answer_in_child(plugin, op, stop, cpu_left, work); });
  if (!child) return std::nullopt;
  if (charge) charge_cpu(child->cpu);
  std::string_view answer(child->bytes);
  if (child->end == process::ChildEnd::answered && !answer.empty() && answer.front() == 'A') {
    child->bytes.erase(0, 1);
    return std::move(child->bytes);
  }
  if (received != nullptr) *received = child->bytes;
  switch (child->end) {
    case process::ChildEnd::answered:
      break;
    case process::ChildEnd::cancelled:
      throw sdk::StoppedError(sdk::StopCause::cancelled, "deadline exceeded: cancelled");
    case process::ChildEnd::wall_backstop:
      throw sdk::StoppedError(sdk::StopCause::wall_backstop,
                              "deadline exceeded: " + plugin.label() + ": " + std::string(op) +
                                  ": still running past the wall-clock backstop, its process "
                                  "killed (stopped: wall_backstop)");
    case process::ChildEnd::too_large:
      crashed(plugin, op,
              "its answer is larger than " + std::to_string(kMaxAnswerBytes) +
                  " bytes, its process killed");
    case process::ChildEnd::signalled:
      if (child->signal == SIGXCPU && cpu_left != nanoseconds::max())
        crashed(plugin, op,
                "SIGXCPU (still running " + std::to_string(kCpuGrace.count()) +
                    " ms of CPU time after its budget was spent)");
      crashed(plugin, op, signal_text(child->signal));
    case process::ChildEnd::exited:
      crashed(plugin, op,
              "its process exited with status " + std::to_string(child->status) + " and no answer");
  }
  if (answer.empty()) crashed(plugin, op, "its process exited with status 0 and no answer");
  if (answer.front() != 'E') crashed(plugin, op, "its process sent a malformed answer");
  throw_failure(plugin, op, answer.substr(1));
}

void rethrow_as_call(const std::exception_ptr& end, const PluginId& plugin, std::string_view op) {
  try {
    std::rethrow_exception(end);
  } catch (const sdk::Error& e) {  // "NAME: execute: SIGNAL" -> "NAME: OP: SIGNAL"
    const std::string execute = plugin.label() + ": execute: ";
    std::string message = e.what();
    if (const auto at = message.find(execute); at != std::string::npos)
      message.replace(at, execute.size(), plugin.label() + ": " + std::string(op) + ": ");
    if (sdk::stop_cause_of(e) != sdk::StopCause::none)
      throw sdk::StoppedError(sdk::stop_cause_of(e), message);
    throw sdk::Error(e.code(), message);
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
