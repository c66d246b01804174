#pragma once
// `flipper repl` on a real pseudo-terminal: a tmux pane on a private socket (killed by that socket
// only), keys sent as a user types them, the screen read back.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "session_fixture.hpp"

namespace flipper::testsupport {

/// Runs a shell command and returns its standard output.
inline std::string shell_output(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  ::pclose(p);
  return out;
}

class Tmux {
 public:
  /// Starts `command` in a 120x60 pane. The pane's shell outlives it (sleep) and prints
  /// `repl-exited-STATUS`, so the last screen and the exit status can be read; the shell ignores
  /// Ctrl-C itself (trap) while the command keeps the default reaction to it.
  explicit Tmux(const std::string& command, const std::string& tag = "")
      : socket_("flipper-repl-test-" + std::to_string(::getpid()) + tag) {
    REQUIRE(!shell_output("command -v tmux").empty());
    shell_output(base() + " new-session -d -x 120 -y 60 -s t \"trap : INT; " + command +
                 "; echo repl-exited-\\$?; sleep 60\" 2>&1");
  }
  Tmux(const Tmux&) = delete;
  Tmux& operator=(const Tmux&) = delete;
  ~Tmux() { shell_output(base() + " kill-server 2>/dev/null"); }

  /// Types `text` and presses Enter.
  void send(const std::string& text) {
    type(text);
    key("Enter");
  }
  /// Types `text` without pressing Enter.
  void type(const std::string& text) { shell_output(base() + " send-keys -t t -l '" + text + "'"); }
  /// Presses a key by tmux name: Enter, Up, C-c, C-d.
  void key(const std::string& name) { shell_output(base() + " send-keys -t t " + name); }

  /// The pane with its scrollback (300 lines), wrapped lines joined.
  std::string screen() {
    return shell_output(base() + " capture-pane -p -J -t t -S -300 2>/dev/null");
  }
  /// The last `n` non-empty-tailed lines of the screen, trailing blank lines dropped.
  std::string last_lines(int n) {
    std::string s = screen();
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    std::size_t start = s.size();
    for (int i = 0; i < n && start != std::string::npos && start > 0; ++i)
      start = s.rfind('\n', start - 1);
    return start == std::string::npos ? s : s.substr(start + 1);
  }

  /// Polls the pane until `text` appears `count` times (up to 30 s).
  bool wait_for(const std::string& text, int count = 1) {
    for (int i = 0; i < 300; ++i) {
      const std::string s = screen();
      int found = 0;
      for (auto pos = s.find(text); pos != std::string::npos; pos = s.find(text, pos + 1)) ++found;
      if (found >= count) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    UNSCOPED_INFO("waited 30 s for '" << text << "' (" << count << "x); the screen:\n" << screen());
    return false;
  }
  /// Types `line`, presses Enter and waits for `expect` to appear `count` times.
  bool ask(const std::string& line, const std::string& expect, int count = 1) {
    send(line);
    return wait_for(expect, count);
  }
  /// The cursor's row in the pane (0 at the top).
  int cursor_y() {
    return std::atoi(shell_output(base() + " display -p -t t '#{cursor_y}'").c_str());
  }
  /// Polls until the cursor is below row `row` (up to 30 s): once a typed line is accepted,
  /// readline has echoed its newline.
  bool wait_for_cursor_below(int row) {
    for (int i = 0; i < 300; ++i) {
      if (cursor_y() > row) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    UNSCOPED_INFO("waited 30 s for the cursor to leave row " << row << "; the screen:\n"
                                                             << screen());
    return false;
  }
  /// Waits for the repl's first prompt.
  bool started() { return wait_for("flipper>"); }
  /// `:quit`, then true when the repl said bye and exited with status 0.
  bool quit() {
    send(":quit");
    return wait_for("bye") && wait_for("repl-exited-0");
  }

 private:
  std::string base() const { return "tmux -L " + socket_ + " -f /dev/null"; }
  std::string socket_;
};

/// `flipper repl` with the test config, a private history file and extra arguments.
inline std::string repl_command(const std::string& history, const std::string& extra = "") {
  std::string cmd =
      "FLIPPER_HISTORY=" + history + " " + std::string(FLIPPER_BINARY_DIR) + "/bin/flipper repl";
  for (const auto& o : test_overrides()) cmd += " --set " + o;
  return cmd + " " + extra;
}

/// A fresh path under build/tests/tmp for a repl test's history or store (old file removed).
inline std::string repl_temp_file(const std::string& name) {
  const std::string path = std::string(FLIPPER_BINARY_DIR) + "/tests/tmp/repl-" + name + "-" +
                           std::to_string(::getpid());
  std::remove(path.c_str());
  return path;
}

}  // namespace flipper::testsupport
