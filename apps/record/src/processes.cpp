// A bounded pool of forked children that contains crashes and hangs (see processes.hpp).
#include "flipper/record/processes.hpp"

#include <sched.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace {

// Each task has a slot in a page shared with its child: what the child was doing when it died
// (written by its signal handler) and what an escaping exception said.
constexpr std::size_t kDuringBytes = 512, kMessageBytes = 1024;
constexpr std::size_t kSlotBytes = kDuringBytes + kMessageBytes;

char* g_slot = nullptr;  // the child's own slot (set in the child only)
int g_backstop_s = 0;    // the child's backstop (set in the child only)

void copy_text(char*& out, const char* end, std::string_view text) {
  for (const char c : text) {
    if (out + 1 >= end) break;
    *out++ = c;
  }
  *out = '\0';
}

// Async-signal-safe: copies the current plugin call's name into the slot, then dies of the
// same signal (SA_RESETHAND restored the default action).
extern "C" void on_fatal_signal(int signal) {
  const kernel::CurrentPluginCall call = kernel::detail::t_current_call;
  if (g_slot != nullptr && call.plugin != nullptr) {
    char* out = g_slot;
    const char* end = g_slot + kDuringBytes;
    copy_text(out, end, "plugin '");
    copy_text(out, end, call.plugin->name);
    copy_text(out, end, "' (");
    copy_text(out, end, call.plugin->file.empty() ? call.plugin->kind : call.plugin->file);
    copy_text(out, end, "): ");
    copy_text(out, end, call.op);
  }
  ::raise(signal);
}

constexpr int kFatalSignals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGALRM};

// In the child: the crash handler on an alternate stack (a stack overflow is a SIGSEGV too),
// and the backstop alarm.
void arm_child(char* slot, int wall_backstop_s) {
  g_slot = slot;
  g_backstop_s = wall_backstop_s;
  static char alternate[64 * 1024];
  stack_t stack{};
  stack.ss_sp = alternate;
  stack.ss_size = sizeof alternate;
  ::sigaltstack(&stack, nullptr);
  struct sigaction action {};
  action.sa_handler = on_fatal_signal;
  action.sa_flags = static_cast<int>(SA_ONSTACK | SA_RESETHAND | SA_NODEFER);
  sigemptyset(&action.sa_mask);
  for (const int s : kFatalSignals) ::sigaction(s, &action, nullptr);
  if (wall_backstop_s > 0) ::alarm(static_cast<unsigned>(wall_backstop_s));
}

std::string slot_text(const char* from, std::size_t size) {
  return {from, strnlen(from, size)};
}

}  // namespace

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::string signal_name(int signal) {
  static const std::map<int, const char*> kNames{
      {SIGSEGV, "SIGSEGV"}, {SIGBUS, "SIGBUS"},   {SIGILL, "SIGILL"},   {SIGFPE, "SIGFPE"},
      {SIGABRT, "SIGABRT"}, {SIGALRM, "SIGALRM"}, {SIGKILL, "SIGKILL"}, {SIGTERM, "SIGTERM"},
      {SIGINT, "SIGINT"},   {SIGPIPE, "SIGPIPE"}, {SIGHUP, "SIGHUP"},   {SIGQUIT, "SIGQUIT"}};
  const auto it = kNames.find(signal);
  return it != kNames.end() ? it->second : "signal " + std::to_string(signal);
}

void restart_backstop() {
  if (g_backstop_s > 0) ::alarm(static_cast<unsigned>(g_backstop_s));
}

std::string ChildExit::kind() const {
  if (status == 0) return "ok";
  if (status < 0) return "not_started";
  if (backstop) return "wall_backstop";
  if (signal != 0) return during.empty() ? "crashed" : "plugin_crashed";
  return "failed";
}

std::string ChildExit::describe() const {
  std::string k = kind();
  if (k == "wall_backstop")
    return k + ": still running at the wall-clock backstop" +
           (during.empty() ? std::string() : ", in " + during);
  if (k == "plugin_crashed") return k + ": " + during + ": " + signal_name(signal);
  if (k == "crashed") return k + ": " + signal_name(signal) + " outside any plugin call";
  if (k == "failed")
    return message.empty() ? "failed: exit status " + std::to_string(status) : message;
  return k;
}

std::vector<ChildExit> run_isolated(
    std::size_t count, const IsolationOptions& options, const std::function<int(std::size_t)>& task,
    const std::function<void(const std::exception&)>& on_exception) {
  std::vector<ChildExit> exits(count);
  if (count == 0) return exits;
  void* shared = ::mmap(nullptr, count * kSlotBytes, PROT_READ | PROT_WRITE,
                        MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (shared == MAP_FAILED) throw std::runtime_error("mmap failed while starting tasks");
  char* slots = static_cast<char*>(shared);
  std::memset(slots, 0, count * kSlotBytes);
  std::map<pid_t, std::size_t> running;
  const std::size_t limit = static_cast<std::size_t>(std::max(1, options.jobs));
  std::size_t next = 0;
  bool failed = false;
  auto wait_one = [&] {
    int raw = 0;
    pid_t pid;
    do pid = ::waitpid(-1, &raw, 0);
    while (pid < 0 && errno == EINTR);
    if (pid < 0) throw std::runtime_error("waitpid failed while running tasks");
    auto it = running.find(pid);
    if (it == running.end()) return;  // not one of ours
    ChildExit& e = exits[it->second];
    const char* slot = slots + it->second * kSlotBytes;
    e.signal = WIFSIGNALED(raw) ? WTERMSIG(raw) : 0;
    e.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + e.signal;
    e.backstop = e.signal == SIGALRM && options.wall_backstop_s > 0;
    e.during = slot_text(slot, kDuringBytes);
    e.message = slot_text(slot + kDuringBytes, kMessageBytes);
    failed = failed || e.status != 0;
    const std::size_t index = it->second;
    running.erase(it);
    if (options.on_exit) options.on_exit(index, e);
  };
  try {
    while (next < count || !running.empty()) {
      if (next < count && (options.keep_going || !failed) && running.size() < limit) {
        // Buffered output would otherwise be written twice, by the child too.
        std::fflush(stdout);
        std::fflush(stderr);
        const pid_t pid = ::fork();
        if (pid < 0) throw std::runtime_error("fork failed while running tasks");
        if (pid == 0) {
          char* slot = slots + next * kSlotBytes;
          arm_child(slot, options.wall_backstop_s);
          int code = 1;
          try {
            code = task(next);
          } catch (const std::exception& ex) {
            const auto* err = dynamic_cast<const sdk::Error*>(&ex);
            char* out = slot + kDuringBytes;
            copy_text(
                out, out + kMessageBytes,
                "[" + std::string(err ? err->code() : sdk::codes::kInternal) + "] " + ex.what());
            if (on_exception) on_exception(ex);
          } catch (...) {
          }
          std::fflush(stdout);
          std::fflush(stderr);
          ::_exit(code);
        }
        running[pid] = next++;
        continue;
      }
      if (running.empty()) break;  // failed: nothing more starts
      wait_one();
    }
  } catch (...) {
    ::munmap(shared, count * kSlotBytes);
    throw;
  }
  ::munmap(shared, count * kSlotBytes);
  return exits;
}

std::vector<int> run_in_processes(std::size_t count, int jobs,
                                  const std::function<int(std::size_t)>& task,
                                  const std::function<void(const std::exception&)>& on_exception) {
  IsolationOptions options;
  options.jobs = jobs;
  options.keep_going = false;
  std::vector<int> status;
  for (const auto& e : run_isolated(count, options, task, on_exception)) status.push_back(e.status);
  return status;
}

}  // namespace flipper::record
