// `flipper repl` on a real pseudo-terminal (tmux): readline prompt, map, candidates, a choice that
// changes the world. tmux runs on a private socket and is killed by that socket only.
#include <unistd.h>
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

#include "session_fixture.hpp"

namespace {

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  pclose(p);
  return out;
}

class Tmux {
 public:
  explicit Tmux(const std::string& command)
      : socket_("flipper-repl-test-" + std::to_string(getpid())) {
    // The pane outlives the repl (sleep) so its last screen can still be read.
    run(base() + " new-session -d -x 120 -y 60 -s t \"" + command +
        "; echo repl-exited-$?; sleep 60\" 2>&1");
  }
  ~Tmux() { run(base() + " kill-server 2>/dev/null"); }
  void send(const std::string& text) {
    run(base() + " send-keys -t t -l '" + text + "'");
    key("Enter");
  }
  void key(const std::string& name) { run(base() + " send-keys -t t " + name); }
  std::string screen() { return run(base() + " capture-pane -p -t t -S -200 2>/dev/null"); }
  /// Polls the pane until `text` appears `count` times (up to 30 s).
  bool wait_for(const std::string& text, int count = 1) {
    for (int i = 0; i < 300; ++i) {
      std::string s = screen();
      int n = 0;
      for (auto pos = s.find(text); pos != std::string::npos; pos = s.find(text, pos + 1)) ++n;
      if (n >= count) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

 private:
  std::string base() const { return "tmux -L " + socket_ + " -f /dev/null"; }
  std::string socket_;
};

}  // namespace

TEST_CASE("repl in a terminal: map, candidates, choosing moves the robot", "[repl][tty]") {
  REQUIRE(run("command -v tmux").size() > 0);
  std::string cmd = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper repl";
  for (const auto& o : flipper::testsupport::test_overrides()) cmd += " --set " + o;
  Tmux tmux(cmd);
  REQUIRE(tmux.wait_for("flipper>"));
  std::string start = tmux.screen();
  CHECK_THAT(start, Catch::Contains(" 4 ##. . R "));
  CHECK_THAT(start, Catch::Contains("Legend:"));

  tmux.send("move right");
  REQUIRE(tmux.wait_for("Choose 1.."));
  CHECK_THAT(tmux.screen(), Catch::Contains("[1] {move right}"));
  tmux.send("1");
  REQUIRE(tmux.wait_for("Done:"));
  CHECK_THAT(tmux.screen(), Catch::Contains(" 4 ##. . . R "));
  // Readline history: Up recalls the last line.
  tmux.send(":map");
  REQUIRE(tmux.wait_for("Legend:", 3));
  tmux.key("Up");
  tmux.key("Enter");
  REQUIRE(tmux.wait_for("Legend:", 4));
  tmux.send(":quit");
  CHECK(tmux.wait_for("bye"));
  CHECK(tmux.wait_for("repl-exited-0"));
}
