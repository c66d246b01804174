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
  explicit Tmux(const std::string& command, const std::string& tag = "")
      : socket_("flipper-repl-test-" + std::to_string(getpid()) + tag) {
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
  /// Types text without pressing Enter.
  void type(const std::string& text) { run(base() + " send-keys -t t -l '" + text + "'"); }
  std::string screen() { return run(base() + " capture-pane -p -J -t t -S -300 2>/dev/null"); }
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

namespace {

// The repl command line with the test config, a private history file and extra arguments.
std::string repl_command(const std::string& history, const std::string& extra = "") {
  std::string cmd = "FLIPPER_HISTORY=" + history + " " + std::string(FLIPPER_BINARY_DIR) +
                    "/bin/flipper repl";
  for (const auto& o : flipper::testsupport::test_overrides()) cmd += " --set " + o;
  return cmd + " " + extra;
}

std::string temp_file(const std::string& name) {
  const std::string path = std::string(FLIPPER_BINARY_DIR) + "/tests/tmp/repl-" + name + "-" +
                           std::to_string(getpid());
  std::remove(path.c_str());
  return path;
}

}  // namespace

TEST_CASE("repl readings: paths on the map, paging with m, choose any, undo", "[repl][tty]") {
  Tmux tmux(repl_command(temp_file("hist1")), "a");
  REQUIRE(tmux.wait_for("flipper>"));
  // Four readings (the parser's ambiguity of `or` and `containing`); session.k = 3 shows three.
  tmux.send("visit room1 or room2 or room3 or room4 containing item is red");
  REQUIRE(tmux.wait_for("m for more"));
  std::string s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("3 of 4 shown. Choose 1..3, m for more, or r to reject all."));
  // Reading 2 ({room1 or room2} or ...) goes to room2 down the x=1 corridor (x=2 is walled at
  // y=2): [1,4] [1,3] [1,2] [1,1].
  CHECK_THAT(s, Catch::Contains("4 steps to [1,1]"));
  CHECK_THAT(s, Catch::Contains(" 4 ##. o R . "));
  CHECK_THAT(s, Catch::Contains(" 2 ##. o ####"));
  CHECK_THAT(s, Catch::Contains(" 1 ##. E . . "));
  // Reading 1 goes right along y=4 to the red circle's stack at [7,4]: path o, end on items E*.
  CHECK_THAT(s, Catch::Contains(" 4 ##. . R o o o o E*"));
  tmux.send("m");
  REQUIRE(tmux.wait_for("4 of 4 shown. Choose 1..4, or r"));
  tmux.send("4");
  REQUIRE(tmux.wait_for("Done:"));
  s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("Done: 5 steps."));
  CHECK_THAT(s, Catch::Contains(" 4 ##. . . o o o o R*"));  // the trail stays until the next command
  CHECK_THAT(s, Catch::Contains("Robot at [7,4]"));
  tmux.send(":undo");
  REQUIRE(tmux.wait_for("Undone:"));
  REQUIRE(tmux.wait_for("Robot at [2,4]", 2));
  tmux.send(":undo");
  REQUIRE(tmux.wait_for("Nothing to undo."));
  tmux.send(":quit");
  CHECK(tmux.wait_for("repl-exited-0"));
}

TEST_CASE("repl typos, collapsed warnings, :define checked line by line, :rules, :delete",
          "[repl][tty]") {
  Tmux tmux(repl_command(temp_file("hist2")), "b");
  REQUIRE(tmux.wait_for("flipper>"));
  tmux.send("vist room1 and pik item");
  REQUIRE(tmux.wait_for("Unknown words:"));
  std::string s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("'vist' (did you mean 'visit'?)"));
  CHECK_THAT(s, Catch::Contains("'pik' (did you mean 'pick'?)"));
  // Five moves left from [2,4]: two succeed, three hit the wall at [-1,4].
  tmux.send("repeat 5 times move left");
  REQUIRE(tmux.wait_for("Choose 1.."));
  CHECK_THAT(tmux.screen(),
             Catch::Contains("warning: 3 \u00d7 Could not complete the action: {move left}"));
  tmux.send("r");
  // The head is checked as typed: core language is not taught.
  tmux.send(":define move up");
  REQUIRE(tmux.wait_for("already means {move up} in the core language"));
  // A bad body line is asked again; an ambiguous one asks which reading; the rest is kept.
  tmux.send(":define zig zag");
  REQUIRE(tmux.wait_for("Defining \"zig zag\""));
  tmux.send("mvoe up");
  REQUIRE(tmux.wait_for("Type the step again"));
  CHECK_THAT(tmux.screen(), Catch::Contains("'mvoe' (did you mean 'move'?)"));
  tmux.send("move up");
  tmux.send("visit room3 or room5 containing item is red");
  REQUIRE(tmux.wait_for("which reading? [1]"));
  CHECK_THAT(tmux.screen(), Catch::Contains("has 2 readings:"));
  tmux.send("2");
  tmux.send("");
  REQUIRE(tmux.wait_for("Learned"));
  s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("{visit {{room3 or room5} containing item {is red}}}"));
  tmux.send(":rules");
  REQUIRE(tmux.wait_for(":delete ID removes"));
  // The id is the first word of the rule line: "  <id>  $... -> zig zag".
  s = tmux.screen();
  const auto at = s.rfind(" -> zig zag");
  REQUIRE(at != std::string::npos);
  const auto line_start = s.rfind('\n', at) + 1;
  std::string id = s.substr(line_start + 2, s.find(' ', line_start + 2) - line_start - 2);
  tmux.send(":delete " + id);
  REQUIRE(tmux.wait_for("Deleted rule " + id + "."));
  tmux.send(":rules");
  REQUIRE(tmux.wait_for("No rules."));
  tmux.send(":quit");
  CHECK(tmux.wait_for("repl-exited-0"));
}

TEST_CASE("repl :cancel abandons a definition, and history persists across runs",
          "[repl][tty]") {
  const std::string history = temp_file("hist3");
  {
    Tmux tmux(repl_command(history), "c");
    REQUIRE(tmux.wait_for("flipper>"));
    tmux.send(":define zig zag");
    REQUIRE(tmux.wait_for(":cancel abandons it."));
    tmux.send("move up");
    tmux.send(":cancel");
    REQUIRE(tmux.wait_for("Definition cancelled; nothing was learned."));
    tmux.send(":rules");
    REQUIRE(tmux.wait_for("No rules."));
    tmux.send("move down");
    REQUIRE(tmux.wait_for("Choose 1.."));
    tmux.send(":quit");
    REQUIRE(tmux.wait_for("repl-exited-0"));
  }
  Tmux again(repl_command(history), "d");
  REQUIRE(again.wait_for("flipper>"));
  again.key("Up");
  again.key("Up");  // :quit, then the line before it
  again.key("Enter");
  REQUIRE(again.wait_for("[1] {move down}"));
  again.send(":quit");
  CHECK(again.wait_for("repl-exited-0"));
}

TEST_CASE("repl on a 3-D world: floors labelled, z kept, other floors listed, :floor",
          "[repl][tty]") {
  const std::string extra = "--config " + std::string(FLIPPER_SOURCE_DIR) +
                            "/configs/octomap-astar.yaml --set lexicon.path=:memory:";
  Tmux tmux(repl_command(temp_file("hist4"), extra), "e");
  REQUIRE(tmux.wait_for("flipper>"));
  std::string s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("Floor z=0 (floors 0..2; :floor N shows another)"));
  CHECK_THAT(s, Catch::Contains("Robot at [1,1,0]"));
  CHECK_THAT(s, Catch::Contains("floor z=2: red square at [1,1,2], yellow circle at [8,6,2],"));
  CHECK_THAT(s, Catch::Contains("blue circle at [5,6,2]"));
  CHECK_THAT(s, Catch::Contains(" 4 . . . . ##. . . . . "));  // the wall x=4 of floor 0
  CHECK_THAT(s, Catch::Contains(" 1 . R . . ##. gt. . . "));
  CHECK_THAT(s, Catch::Contains("room3 (x 0..9, y 0..3, z 2)"));
  tmux.send(":floor 1");  // the ceiling of floor 0: walls but one passage at [8,1]
  REQUIRE(tmux.wait_for("Floor z=1"));
  CHECK_THAT(tmux.screen(), Catch::Contains(" 1 ################. ##"));
  tmux.send(":floor 2");
  REQUIRE(tmux.wait_for("Floor z=2"));
  CHECK_THAT(tmux.screen(), Catch::Contains("floor z=0: red circle at [2,6,0]"));
  tmux.send(":quit");
  CHECK(tmux.wait_for("repl-exited-0"));
}

TEST_CASE("a second repl on the same store sees a new rule without a restart", "[repl][tty]") {
  const std::string store = temp_file("store.sqlite");
  const std::string set = "--set lexicon.path=" + store;
  Tmux first(repl_command(temp_file("hist5"), set), "f");
  Tmux second(repl_command(temp_file("hist6"), set), "g");
  REQUIRE(first.wait_for("flipper>"));
  REQUIRE(second.wait_for("flipper>"));
  second.send("zig zag");
  REQUIRE(second.wait_for("I did not understand that."));
  first.send(":define zig zag");
  REQUIRE(first.wait_for(":cancel abandons it."));
  first.send("move up");
  first.send("move right");
  first.send("");
  REQUIRE(first.wait_for("can use it from their next query on"));
  // The second process was started before the rule existed.
  second.send("zig zag");
  REQUIRE(second.wait_for("[1] {{move up};{move right}}"));
  first.send(":quit");
  second.send(":quit");
  CHECK(first.wait_for("repl-exited-0"));
  CHECK(second.wait_for("repl-exited-0"));
}
