#pragma once
// A child process with its stdin and stdout on pipes, for tests and benchmarks that drive a built
// binary line by line (`flipper session`, the lexicon kill driver). Free of Catch2 so benchmarks
// can use it too: failures to start throw std::runtime_error.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace flipper::testsupport {

class ChildProcess {
 public:
  /// Starts `args[0]` with the arguments `args[1..]`.
  explicit ChildProcess(std::vector<std::string> args) {
    if (args.empty()) throw std::runtime_error("ChildProcess: no program given");
    // A child that died must make writes fail, not end this process with SIGPIPE.
    signal(SIGPIPE, SIG_IGN);
    std::vector<char*> argv;  // built before fork: the child only calls async-signal-safe code
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // Close-on-exec: a sibling started at the same time from another thread must not inherit
    // these ends (it would keep this child's input open, and this child would never see EOF).
    int in[2], out[2];
    if (pipe2(in, O_CLOEXEC) != 0) throw std::runtime_error("ChildProcess: pipe failed");
    if (pipe2(out, O_CLOEXEC) != 0) {
      close_pair(in);
      throw std::runtime_error("ChildProcess: pipe failed");
    }
    pid_ = fork();
    if (pid_ < 0) {
      close_pair(in);
      close_pair(out);
      throw std::runtime_error("ChildProcess: fork failed");
    }
    if (pid_ == 0) {
      // A test that crashes takes its child with it: a server left running would hold the test
      // runner's output pipe open until ctest's timeout. (The signal follows the forking thread:
      // start children from threads that outlive them.)
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      dup2(in[0], STDIN_FILENO);
      dup2(out[1], STDOUT_FILENO);
      close_pair(in);
      close_pair(out);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to_ = in[1];
    from_ = out[0];
    // Children started later must not inherit this child's pipe ends: a copy of the input's
    // write end would keep this child from ever seeing the end of its input.
    fcntl(to_, F_SETFD, FD_CLOEXEC);
    fcntl(from_, F_SETFD, FD_CLOEXEC);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  /// A child still running is killed (SIGKILL) and reaped.
  ~ChildProcess() {
    close_input();
    if (from_ >= 0) close(from_);
    kill_now();
  }

  pid_t pid() const { return pid_; }

  /// Writes `line` and a newline; false when the child no longer reads its input.
  bool write_line(const std::string& line) {
    const std::string l = line + "\n";
    for (std::size_t done = 0; done < l.size();) {
      const ssize_t n = ::write(to_, l.data() + done, l.size() - done);
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }

  /// The next line the child writes, without its newline; empty at the end of its output or when
  /// none arrives within `timeout` (the programs driven here never write empty lines).
  std::string read_line(std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
    for (;;) {
      if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return line;
      }
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(timeout.count())) <= 0 || !fill()) return {};
    }
  }

  /// Everything not read yet, up to the end of the child's output (waits for it to close).
  std::string read_all() {
    while (fill()) {
    }
    return std::exchange(buffer_, {});
  }

  /// SIGKILL now and reap; no-op once the child has been reaped.
  void kill_now() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

  /// Closes the child's input and waits for it to exit: its exit code, or -1 if a signal ended it.
  int finish() {
    close_input();
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  static void close_pair(const int (&fds)[2]) {
    close(fds[0]);
    close(fds[1]);
  }
  void close_input() {
    if (to_ >= 0) close(to_);
    to_ = -1;
  }
  /// Appends one read's worth of output to the buffer; false at the end of output.
  bool fill() {
    char chunk[65536];
    const ssize_t n = ::read(from_, chunk, sizeof chunk);
    if (n <= 0) return false;
    buffer_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  std::string buffer_;
};

}  // namespace flipper::testsupport
