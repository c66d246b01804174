#pragma once
// Load for determinism tests (docs/planners.md §4): child processes that spin on a CPU each
// until they are killed. The constructor returns once every child has started spinning (each
// writes a byte to a pipe first, so the test waits on a condition, not a sleep); the destructor
// kills and reaps them, so a failing check cannot leave them behind.
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace flipper::testsupport {

class CpuBurners {
 public:
  explicit CpuBurners(int count) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    for (int i = 0; i < count; ++i) {
      const pid_t pid = fork();
      if (pid < 0) {
        stop();
        throw std::runtime_error("fork failed");
      }
      if (pid == 0) {  // the child: say it runs, then spin until killed
        close(fds[0]);
        const char ready = 1;
        if (write(fds[1], &ready, 1) != 1) _exit(1);
        close(fds[1]);
        volatile std::uint64_t spins = 0;
        for (;;) spins = spins + 1;
      }
      pids_.push_back(pid);
    }
    close(fds[1]);
    char byte = 0;
    for (int started = 0; started < count;) {
      const ssize_t n = read(fds[0], &byte, 1);
      if (n == 1) {
        ++started;
      } else if (n == 0 || errno != EINTR) {
        close(fds[0]);
        stop();
        throw std::runtime_error("a burner did not start");
      }
    }
    close(fds[0]);
  }
  CpuBurners(const CpuBurners&) = delete;
  CpuBurners& operator=(const CpuBurners&) = delete;
  ~CpuBurners() { stop(); }

  /// CPU time (clock ticks) the burners have used so far, from /proc/<pid>/stat.
  std::uint64_t cpu_ticks() const {
    std::uint64_t total = 0;
    for (const pid_t pid : pids_) {
      FILE* f = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
      if (f == nullptr) continue;
      char buf[1024] = {};
      const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
      std::fclose(f);
      // Fields after the command's closing parenthesis: state is 3, utime 14, stime 15.
      const std::string stat(buf, n);
      const std::size_t close = stat.rfind(')');
      if (close == std::string::npos) continue;
      std::vector<std::string> fields;
      std::size_t at = close + 2;
      while (at < stat.size() && fields.size() < 13) {
        const std::size_t end = stat.find(' ', at);
        fields.push_back(stat.substr(at, end - at));
        if (end == std::string::npos) break;
        at = end + 1;
      }
      if (fields.size() == 13) total += std::stoull(fields[11]) + std::stoull(fields[12]);
    }
    return total;
  }

 private:
  void stop() {
    for (const pid_t pid : pids_) {
      kill(pid, SIGKILL);
      while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
      }
    }
    pids_.clear();
  }

  std::vector<pid_t> pids_;
};

}  // namespace flipper::testsupport
