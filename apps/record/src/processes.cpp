// A bounded pool of forked children (see processes.hpp).
#include "flipper/record/processes.hpp"

#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <thread>

namespace flipper::record {

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::vector<int> run_in_processes(std::size_t count, int jobs,
                                  const std::function<int(std::size_t)>& task,
                                  const std::function<void(const std::exception&)>& on_exception) {
  std::vector<int> status(count, -1);
  std::map<pid_t, std::size_t> running;
  const std::size_t limit = static_cast<std::size_t>(std::max(1, jobs));
  std::size_t next = 0;
  bool failed = false;
  auto wait_one = [&] {
    int raw = 0;
    pid_t pid;
    do pid = ::waitpid(-1, &raw, 0);
    while (pid < 0 && errno == EINTR);
    if (pid < 0) throw std::runtime_error("waitpid failed while running variants");
    auto it = running.find(pid);
    if (it == running.end()) return;  // not one of ours
    const int code = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    status[it->second] = code;
    failed = failed || code != 0;
    running.erase(it);
  };
  while (next < count || !running.empty()) {
    if (next < count && !failed && running.size() < limit) {
      // Buffered output would otherwise be written twice, by the child too.
      std::fflush(stdout);
      std::fflush(stderr);
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error("fork failed while running variants");
      if (pid == 0) {
        int code = 1;
        try {
          code = task(next);
        } catch (const std::exception& e) {
          if (on_exception) on_exception(e);
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
  return status;
}

}  // namespace flipper::record
