// `flipper repl` on a real pseudo-terminal (tmux, tests/support/tmux_repl.hpp): readline prompt,
// map, candidates, choices that change the world, definitions, Ctrl-C, history, 3-D floors.
#include <catch2/catch.hpp>

#include "tmux_repl.hpp"

using flipper::testsupport::repl_command;
using flipper::testsupport::repl_temp_file;
using flipper::testsupport::Tmux;

TEST_CASE("repl in a terminal: map, candidates, choosing moves the robot", "[repl][tty]") {
  Tmux tmux(repl_command(repl_temp_file("hist0")));
  REQUIRE(tmux.started());
  const std::string start = tmux.screen();
  CHECK_THAT(start, Catch::Contains(" 4 ##. . R "));
  CHECK_THAT(start, Catch::Contains("Legend:"));

  REQUIRE(tmux.ask("move right", "Choose 1.."));
  CHECK_THAT(tmux.screen(), Catch::Contains("[1] {move right}"));
  REQUIRE(tmux.ask("1", "Done:"));
  CHECK(tmux.wait_for(" 4 ##. . . R "));  // the map after the move comes after "Done:"
  // Readline history: Up recalls the last line.
  REQUIRE(tmux.ask(":map", "Legend:", 3));
  tmux.key("Up");
  tmux.key("Enter");
  REQUIRE(tmux.wait_for("Legend:", 4));
  CHECK(tmux.quit());
}

TEST_CASE("repl readings: paths on the map, paging with m, choose any, undo", "[repl][tty]") {
  Tmux tmux(repl_command(repl_temp_file("hist1")), "a");
  REQUIRE(tmux.started());
  // Four readings (the parser's ambiguity of `or` and `containing`); session.k = 3 shows three.
  REQUIRE(tmux.ask("visit room1 or room2 or room3 or room4 containing item is red", "m for more"));
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
  REQUIRE(tmux.ask("m", "4 of 4 shown. Choose 1..4, or r"));
  REQUIRE(tmux.ask("4", "Done:"));
  // The map after the move is drawn after "Done:": read the screen once it is all there.
  REQUIRE(tmux.wait_for("Robot at [7,4]"));
  s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("Done: 5 steps."));
  CHECK_THAT(s,
             Catch::Contains(" 4 ##. . . o o o o R*"));  // the trail stays until the next command
  CHECK_THAT(s, Catch::Contains("Robot at [7,4]"));
  REQUIRE(tmux.ask(":undo", "Undone:"));
  REQUIRE(tmux.wait_for("Robot at [2,4]", 2));
  REQUIRE(tmux.ask(":undo", "Nothing to undo."));
  CHECK(tmux.quit());
}

TEST_CASE("repl typos, collapsed warnings, :define checked line by line, :rules, :delete",
          "[repl][tty]") {
  Tmux tmux(repl_command(repl_temp_file("hist2")), "b");
  REQUIRE(tmux.started());
  REQUIRE(tmux.ask("vist room1 and pik item", "Unknown words:"));
  std::string s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("'vist' (did you mean 'visit'?)"));
  CHECK_THAT(s, Catch::Contains("'pik' (did you mean 'pick'?)"));
  // Five moves left from [2,4]: two succeed, three hit the wall at [-1,4].
  REQUIRE(tmux.ask("repeat 5 times move left", "Choose 1.."));
  CHECK_THAT(tmux.screen(),
             Catch::Contains("warning: 3 \u00d7 Could not complete the action: {move left}"));
  tmux.send("r");
  // The head is checked as typed: core language is not taught.
  REQUIRE(tmux.ask(":define move up", "already means {move up} in the core language"));
  // A bad body line is asked again; an ambiguous one asks which reading; the rest is kept.
  REQUIRE(tmux.ask(":define zig zag", "Defining \"zig zag\""));
  REQUIRE(tmux.ask("mvoe up", "Type the step again"));
  CHECK_THAT(tmux.screen(), Catch::Contains("'mvoe' (did you mean 'move'?)"));
  tmux.send("move up");
  REQUIRE(tmux.ask("visit room3 or room5 containing item is red", "which reading? [1]"));
  CHECK_THAT(tmux.screen(), Catch::Contains("has 2 readings:"));
  tmux.send("2");
  REQUIRE(tmux.ask("", "Learned"));
  CHECK_THAT(tmux.screen(), Catch::Contains("{visit {{room3 or room5} containing item {is red}}}"));
  REQUIRE(tmux.ask(":rules", ":delete ID removes"));
  // The id is the first word of the rule line: "  <id>  $... -> zig zag".
  s = tmux.screen();
  const auto at = s.rfind(" -> zig zag");
  REQUIRE(at != std::string::npos);
  const auto line_start = s.rfind('\n', at) + 1;
  const std::string id = s.substr(line_start + 2, s.find(' ', line_start + 2) - line_start - 2);
  REQUIRE(tmux.ask(":delete " + id, "Deleted rule " + id + "."));
  REQUIRE(tmux.ask(":rules", "No rules."));
  CHECK(tmux.quit());
}

TEST_CASE("repl Ctrl-C drops the line or the definition, never the repl, and Ctrl-D leaves",
          "[repl][tty]") {
  Tmux tmux(repl_command(repl_temp_file("hist7")), "h");
  REQUIRE(tmux.started());
  // Mid-line: the typed text stays on screen with ^C, a fresh prompt follows. (Ctrl-C flushes
  // the terminal's unread input, so the test waits until the text is echoed, as a person would.)
  tmux.type("move ri");
  REQUIRE(tmux.wait_for("flipper> move ri"));
  tmux.key("C-c");
  REQUIRE(tmux.wait_for("move ri^C"));
  CHECK(tmux.last_lines(2) == "flipper> move ri^C\nflipper>");
  // The dropped text is gone: the next line is read on its own.
  REQUIRE(tmux.ask("move up", "Choose 1.."));
  CHECK_THAT(tmux.screen(), Catch::Contains("[1] {move up}"));
  // At an empty prompt, once and again: a hint, and the repl is still there.
  tmux.key("C-c");
  REQUIRE(tmux.wait_for("(:quit or Ctrl-D leaves)"));
  CHECK(tmux.last_lines(3) == "flipper> ^C\n(:quit or Ctrl-D leaves)\nflipper>");
  tmux.key("C-c");
  REQUIRE(tmux.wait_for("(:quit or Ctrl-D leaves)", 2));
  REQUIRE(tmux.ask(":map", "Legend:", 2));
  // Mid-definition: the steps typed so far are dropped, nothing is learned.
  REQUIRE(tmux.ask(":define zig zag", "Ctrl-C (or :cancel) abandons it."));
  REQUIRE(tmux.ask("move up", "  ...>", 2));  // the step is checked, the next one is asked for
  tmux.type("move ri");
  REQUIRE(tmux.wait_for("  ...> move ri"));
  tmux.key("C-c");
  REQUIRE(tmux.wait_for("Definition cancelled; nothing was learned."));
  CHECK(tmux.last_lines(3) ==
        "  ...> move ri^C\nDefinition cancelled; nothing was learned.\nflipper>");
  REQUIRE(tmux.ask(":rules", "No rules."));
  REQUIRE(tmux.ask("zig zag", "I did not understand that."));
  // Ctrl-D at an empty prompt leaves.
  tmux.key("C-d");
  CHECK(tmux.wait_for("bye"));
  CHECK(tmux.wait_for("repl-exited-0"));
}

TEST_CASE("repl Ctrl-C during a long query drops its answer and keeps the repl", "[repl][tty]") {
  // OMPL's rrtstar refining for its whole budget of 20,000 iterations: `visit room1` takes
  // about a second to plan (more on a loaded or instrumented build).
  const std::string slow =
      "--set planner.plugin=ompl --set planner.params.planner=rrtstar "
      "--set planner.params.iterations=0 --set planner.params.max_iterations=20000";
  Tmux tmux(repl_command(repl_temp_file("hist8"), slow), "i");
  REQUIRE(tmux.started());
  tmux.type("visit room1");
  REQUIRE(tmux.wait_for("flipper> visit room1"));
  const int prompt_row = tmux.cursor_y();
  tmux.key("Enter");
  // Ctrl-C once the line is taken: a terminal drops the input not yet read when it signals, so a
  // Ctrl-C right behind the Enter could cancel the line instead of the query.
  REQUIRE(tmux.wait_for_cursor_below(prompt_row));
  tmux.key("C-c");
  REQUIRE(tmux.wait_for("Cancelled (Ctrl-C): the readings are not shown."));
  CHECK(tmux.last_lines(4) ==
        "flipper> visit room1\n^C\nCancelled (Ctrl-C): the readings are not shown.\nflipper>");
  // Nothing to choose from the dropped answer; the next query works.
  REQUIRE(tmux.ask("move up", "Choose 1.."));
  CHECK_THAT(tmux.screen(), Catch::Contains("[1] {move up}"));
  CHECK(tmux.quit());
}

TEST_CASE("repl :cancel abandons a definition, and history persists across runs", "[repl][tty]") {
  const std::string history = repl_temp_file("hist3");
  {
    Tmux tmux(repl_command(history), "c");
    REQUIRE(tmux.started());
    REQUIRE(tmux.ask(":define zig zag", ":cancel) abandons it."));
    tmux.send("move up");
    REQUIRE(tmux.ask(":cancel", "Definition cancelled; nothing was learned."));
    REQUIRE(tmux.ask(":rules", "No rules."));
    REQUIRE(tmux.ask("move down", "Choose 1.."));
    REQUIRE(tmux.quit());
  }
  Tmux again(repl_command(history), "d");
  REQUIRE(again.started());
  again.key("Up");
  again.key("Up");  // :quit, then the line before it
  again.key("Enter");
  REQUIRE(again.wait_for("[1] {move down}"));
  CHECK(again.quit());
}

TEST_CASE("repl on a 3-D world: floors labelled, z kept, other floors listed, :floor",
          "[repl][tty]") {
  const std::string extra = "--config " + std::string(FLIPPER_SOURCE_DIR) +
                            "/configs/octomap-astar.yaml --set lexicon.path=:memory:";
  Tmux tmux(repl_command(repl_temp_file("hist4"), extra), "e");
  REQUIRE(tmux.started());
  const std::string s = tmux.screen();
  CHECK_THAT(s, Catch::Contains("Floor z=0 (floors 0..2; :floor N shows another)"));
  CHECK_THAT(s, Catch::Contains("Robot at [1,1,0]"));
  CHECK_THAT(s, Catch::Contains("floor z=2: red square at [1,1,2], yellow circle at [8,6,2],"));
  CHECK_THAT(s, Catch::Contains("blue circle at [5,6,2]"));
  CHECK_THAT(s, Catch::Contains(" 4 . . . . ##. . . . . "));  // the wall x=4 of floor 0
  CHECK_THAT(s, Catch::Contains(" 1 . R . . ##. gt. . . "));
  CHECK_THAT(s, Catch::Contains("room3 (x 0..9, y 0..3, z 2)"));
  // The ceiling of floor 0: walls but one passage at [8,1].
  REQUIRE(tmux.ask(":floor 1", "Floor z=1"));
  CHECK_THAT(tmux.screen(), Catch::Contains(" 1 ################. ##"));
  REQUIRE(tmux.ask(":floor 2", "Floor z=2"));
  CHECK_THAT(tmux.screen(), Catch::Contains("floor z=0: red circle at [2,6,0]"));
  // Floors 0..2: 3 is one past the top, -1 one below the bottom.
  REQUIRE(tmux.ask(":floor 3", "There is no floor 3: this world's floors go from z = 0 to 2."));
  REQUIRE(tmux.ask(":floor -1", "There is no floor -1: this world's floors go from z = 0 to 2."));
  CHECK(tmux.quit());
}

TEST_CASE("a second repl on the same store sees a new rule without a restart", "[repl][tty]") {
  const std::string set = "--set lexicon.path=" + repl_temp_file("store.sqlite");
  Tmux first(repl_command(repl_temp_file("hist5"), set), "f");
  Tmux second(repl_command(repl_temp_file("hist6"), set), "g");
  REQUIRE(first.started());
  REQUIRE(second.started());
  REQUIRE(second.ask("zig zag", "I did not understand that."));
  REQUIRE(first.ask(":define zig zag", ":cancel) abandons it."));
  first.send("move up");
  first.send("move right");
  REQUIRE(first.ask("", "can use it from their next query on"));
  // The second process was started before the rule existed.
  REQUIRE(second.ask("zig zag", "[1] {{move up};{move right}}"));
  CHECK(first.quit());
  CHECK(second.quit());
}
