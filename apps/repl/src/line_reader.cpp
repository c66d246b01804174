// Line input: GNU readline for terminals (editing, history kept across runs, Ctrl-C cancels the
// line being typed), std::getline otherwise.
//
// Ctrl-C: readline's blocking readline() retries its read after a signal, so a flag set by a
// SIGINT handler is seen only at the next key. Instead readline's callback interface is driven
// from our own poll() on stdin and a self-pipe the handler writes to: the poll wakes at once and
// the line is dropped. The handler stays installed while the repl runs, so Ctrl-C during a query
// never ends the program (the repl drops that answer: take_interrupt).
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <readline/history.h>
#include <readline/readline.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <istream>
#include <memory>

#include "flipper/repl/repl.hpp"

namespace flipper::repl {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
int g_wake[2] = {-1, -1};  // self-pipe: the SIGINT handler writes, the line reader polls

extern "C" void on_sigint(int) {
  const int saved = errno;
  g_interrupted = 1;
  const char byte = 1;
  [[maybe_unused]] const auto n = ::write(g_wake[1], &byte, 1);
  errno = saved;
}

void drain_wake_pipe() {
  char buf[64];
  while (::read(g_wake[0], buf, sizeof buf) > 0) {
  }
}

// Where readline's callback delivers a finished line (one reader reads at a time).
struct Delivery {
  bool done = false;
  bool eof = false;
  std::string line;
};
Delivery* g_delivery = nullptr;

extern "C" void on_line(char* raw) {
  // Removed here, not after: readline would otherwise print the next prompt right away.
  rl_callback_handler_remove();
  g_delivery->done = true;
  g_delivery->eof = raw == nullptr;
  if (raw != nullptr) g_delivery->line.assign(raw);
  std::free(raw);
}

class ReadlineReader : public LineReader {
 public:
  explicit ReadlineReader(std::string history_file) : history_file_(std::move(history_file)) {
    if (!history_file_.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(std::filesystem::path(history_file_).parent_path(), ec);
      read_history(history_file_.c_str());
    }
    if (::pipe2(g_wake, O_NONBLOCK | O_CLOEXEC) != 0) g_wake[0] = g_wake[1] = -1;
    rl_catch_signals = 0;  // SIGINT is ours (readline would re-raise it and end the program)
    // Readline keeps its SIGWINCH handler while a line is read, not only while a key is handled,
    // so a resize during the poll is noticed (rl_check_signals below).
    rl_persistent_signal_handlers = 1;
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;  // the session's own reads and writes are not disturbed
    sigaction(SIGINT, &sa, &previous_);
  }
  ReadlineReader(const ReadlineReader&) = delete;
  ReadlineReader& operator=(const ReadlineReader&) = delete;
  ~ReadlineReader() override {
    sigaction(SIGINT, &previous_, nullptr);
    for (int& fd : g_wake) {
      if (fd >= 0) ::close(fd);
      fd = -1;
    }
  }

  Read read(const char* prompt, std::string& line) override {
    take_interrupt();  // a Ctrl-C pressed while nothing was read is spent
    Delivery delivery;
    g_delivery = &delivery;
    rl_callback_handler_install(prompt, on_line);
    while (!delivery.done) {
      pollfd fds[2] = {{STDIN_FILENO, POLLIN, 0}, {g_wake[0], POLLIN, 0}};
      const int ready = ::poll(fds, g_wake[0] >= 0 ? 2 : 1, -1);
      if (g_interrupted) {
        line.assign(rl_line_buffer == nullptr ? "" : rl_line_buffer);
        cancel_line();
        take_interrupt();
        g_delivery = nullptr;
        return Read::interrupted;
      }
      if (ready < 0 && errno == EINTR) {
        rl_check_signals();  // a window resize: readline redraws the line for the new width
        continue;
      }
      if (ready < 0) break;
      if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) rl_callback_read_char();
    }
    g_delivery = nullptr;
    if (!delivery.done) rl_callback_handler_remove();
    if (!delivery.done || delivery.eof) return Read::end;
    line = std::move(delivery.line);
    remember(line);
    return Read::line;
  }

  bool take_interrupt() override {
    const bool was = g_interrupted != 0;
    g_interrupted = 0;
    if (g_wake[0] >= 0) drain_wake_pipe();
    return was;
  }

 private:
  // Leaves the typed text on screen followed by ^C (as shells do) and forgets it.
  static void cancel_line() {
    rl_free_line_state();
    rl_callback_sigcleanup();
    rl_point = rl_end;
    rl_redisplay();
    std::fputs("^C\n", rl_outstream != nullptr ? rl_outstream : stdout);
    rl_replace_line("", 0);
    rl_callback_handler_remove();
  }

  void remember(const std::string& line) {
    if (line.empty()) return;
    add_history(line.c_str());
    if (history_file_.empty()) return;
    // Appended per line, so a crash or a second window loses nothing typed.
    if (append_history(1, history_file_.c_str()) != 0) write_history(history_file_.c_str());
    history_truncate_file(history_file_.c_str(), 1000);
  }

  std::string history_file_;
  struct sigaction previous_ {};
};

class StreamReader : public LineReader {
 public:
  explicit StreamReader(std::istream& in) : in_(in) {}
  Read read(const char*, std::string& line) override {
    if (!std::getline(in_, line)) return Read::end;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return Read::line;
  }

 private:
  std::istream& in_;
};

}  // namespace

std::string default_history_file() {
  if (const char* f = std::getenv("FLIPPER_HISTORY")) return f;
  const char* home = std::getenv("HOME");
  if (home == nullptr || *home == '\0') return {};
  return std::string(home) + "/.local/share/flipper/repl_history";
}

std::unique_ptr<LineReader> make_line_reader(std::istream& in, bool terminal,
                                             const std::string& history_file) {
  if (terminal) return std::make_unique<ReadlineReader>(history_file);
  return std::make_unique<StreamReader>(in);
}

}  // namespace flipper::repl
