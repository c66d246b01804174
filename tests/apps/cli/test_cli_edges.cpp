// The command line's rough edges, each as a user meets it: defaults of a config kept outside
// configs/, switching a plugin with --set, `config explain` (optional sections, plugin params,
// wrapping), unknown commands, word suggestions, `run`'s hints and warnings, --json for every
// outcome, and a world meant for the other world plugin.
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"

using namespace flipper::clitest;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kSrc = FLIPPER_SOURCE_DIR;

// Runs flipper from `dir` (see test_paths.cpp): stdout and stderr merged.
Run run_from(const fs::path& dir, const std::string& args) {
  return run_flipper("--version >/dev/null && cd '" + dir.string() + "' && " +
                     std::string(FLIPPER_BINARY_DIR) + "/bin/flipper " + args);
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("a config kept outside configs/ that extends the default finds the default's files",
          "[cli][config]") {
  const fs::path dir = fs::path(scratch_dir("edges-extends"));
  fs::create_directories(dir / "elsewhere");
  std::ofstream(dir / "my.yaml") << "extends: " << kSrc << "/configs/default.yaml\n"
                                 << "session: {k: 4}\n";
  // world.file and grammar.file are written in no file: they resolve against the default
  // configs directory, not against my.yaml's (which has no worlds/ or grammars/).
  const Run ok = run_from(dir / "elsewhere", "config check ../my.yaml --set lexicon.path=:memory:");
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(contains(ok.out, "  k: 4\n"));
  const Run run = run_from(dir / "elsewhere",
                           "run --config ../my.yaml --set lexicon.path=:memory: 'visit room1'");
  INFO(run.out);
  CHECK(run.status == 0);
  CHECK(contains(run.out, "robot: [9,0]"));
}

TEST_CASE("switching a plugin with --set drops the params the files gave the other plugin",
          "[cli][config]") {
  const fs::path dir = fs::path(scratch_dir("edges-switch"));
  fs::create_directories(dir);
  std::ofstream(dir / "ompl.yaml") << "extends: " << kSrc << "/configs/default.yaml\n"
                                   << "planner: {plugin: ompl, params: {seed: 7}}\n";
  const std::string config = "--config " + (dir / "ompl.yaml").string();
  // Before: "unknown config key 'planner.params.seed'" (astar has no seed).
  const Run run = run_flipper(
      "run " + config + " --set planner.plugin=astar --set lexicon.path=:memory: 'visit room1'");
  INFO(run.out);
  CHECK(run.status == 0);
  CHECK(contains(run.out, "robot: [9,0]"));
  const Run astar = run_flipper("config print " + config + " --set planner.plugin=astar");
  INFO(astar.out);
  CHECK(astar.status == 0);
  CHECK(contains(astar.out, "planner:\n  plugin: astar\n"));
  CHECK_FALSE(contains(astar.out, "seed"));
  // The same plugin again keeps the file's params.
  const Run same = run_flipper("config print " + config + " --set planner.plugin=ompl");
  CHECK(contains(same.out, "seed: 7"));
  // Params the user gave with --set before switching are theirs: kept.
  const Run mine = run_flipper("config print " + config +
                               " --set planner.params.heuristic=none --set planner.plugin=astar");
  INFO(mine.out);
  CHECK(mine.status == 0);
  CHECK(contains(mine.out, "heuristic: none"));
  CHECK_FALSE(contains(mine.out, "seed"));
}

TEST_CASE("config explain: optional sections, the selected plugins' params, wrapped lines",
          "[cli][config]") {
  const Run rewriter = run_flipper("config explain rewriter");
  INFO(rewriter.out);
  CHECK(rewriter.status == 0);
  // The default column wraps at 24 characters: "(none; needed with" / "rewriter)".
  CHECK(contains(rewriter.out, "rewriter.plugin  string  (none; needed with "));
  CHECK(contains(rewriter.out, "\n" + std::string(25, ' ') + "rewriter)\n"));
  CHECK_FALSE(contains(rewriter.out, "(required)"));
  // The rewriter section also lists its plugin's params (rewrites).
  CHECK(contains(rewriter.out, "\nrewriter.params: plugin rewrites "));

  const Run one = run_flipper("config explain planner.params.heuristic");
  INFO(one.out);
  CHECK(one.status == 0);
  CHECK(contains(one.out, "planner.params: plugin astar "));
  CHECK(contains(one.out, "  planner.params.heuristic "));
  CHECK(count(one.out, "planner.params.") == 1);  // that one row only

  const Run all = run_flipper("config explain");
  CHECK(all.status == 0);
  for (const char* section : {"world", "planner", "parser", "scorer", "rewriter", "similarity"})
    CHECK(contains(all.out, std::string("\n") + section + ".params: plugin "));
  CHECK(contains(all.out, "  parser.params.beam "));

  // Wrapped to the terminal's width ($COLUMNS when not a terminal); lines were 254 wide.
  const Run wide = run_shell("COLUMNS=140 " + std::string(FLIPPER_BINARY_DIR) +
                             "/bin/flipper config explain 2>&1");
  REQUIRE(wide.status == 0);
  std::istringstream lines(wide.out);
  std::size_t longest = 0;
  for (std::string line; std::getline(lines, line);) longest = std::max(longest, line.size());
  CHECK(longest <= 140);
  CHECK(longest >= 100);  // the width is used, not a fixed narrow one

  const Run typo = run_flipper("config explain planner.params.heuristc");
  CHECK(typo.status == 2);
  CHECK(contains(typo.out,
                 "no config key or section 'planner.params.heuristc' (did you mean "
                 "'planner.params.heuristic'?)"));
}

TEST_CASE("an unknown command is named, with a suggestion only within a typo's distance",
          "[cli][format]") {
  const Run runn = run_flipper("runn 'move up'");
  CHECK(runn.status == 2);
  CHECK(runn.out ==
        "flipper: [usage] unknown command 'runn' (did you mean 'run'?); the commands are "
        "plugins, plugin, config, run, session, repl, replay, bench, runs, lexicon, serve, dds, "
        "accounts, frontend (see --help)\n");
  const Run far = run_flipper("zzz");
  CHECK(far.status == 2);
  CHECK(contains(far.out, "unknown command 'zzz'; the commands are"));
}

TEST_CASE("run: did you mean, plain words, repeated warnings collapsed", "[cli][run]") {
  const Run vist = run_flipper("run --set lexicon.path=:memory: 'vist room1'");
  CHECK(vist.status == 1);
  CHECK(contains(vist.out, "Unknown word: 'vist' (did you mean 'visit'?)"));

  const Run go = run_flipper("run --set lexicon.path=:memory: 'go up'");
  CHECK(go.status == 1);
  CHECK(contains(go.out, "'go' (the core language says 'visit PLACE or move DIRECTION')"));
  CHECK_FALSE(contains(go.out, "did you mean '+'"));

  // From [2,4] two steps left reach [0,4]; the other 28 are blocked by the wall at [-1,4].
  const Run wall = run_flipper("run --set lexicon.path=:memory: 'repeat 30 times move left'");
  INFO(wall.out);
  CHECK(wall.status == 0);
  CHECK(count(wall.out, "warning:") == 1);
  CHECK(contains(
      wall.out,
      "warning: 28 \u00d7 Could not complete the action: {move left} ([-1,4] is a wall)\n"));
}

TEST_CASE("with --json every outcome is one JSON object on stdout, errors included",
          "[cli][format]") {
  struct Case {
    std::string args;
    int status;
    std::string code;
  };
  const Case cases[] = {
      {"run --json --set session.k=0 '{move up}'", 2, "bad_config"},
      {"run --json --set lexicon.path=:memory: zorp", 1, "bad_program"},
      {"run --json", 2, "usage"},
      {"run --json --world /no/such/world.json '{move up}'", 2, "bad_world"},
      {"config check --json --set session.k=0", 2, "bad_config"},
      {"lexicon list --json --set lexicon.path=/no/such/dir/x.sqlite", 2, "bad_config"},
  };
  for (const auto& c : cases) {
    INFO(c.args);
    const Run r = run_flipper(c.args);  // stderr merged: it must add nothing
    INFO(r.out);
    CHECK(r.status == c.status);
    json j;
    REQUIRE_NOTHROW(j = json::parse(r.out));
    CHECK(j["ok"] == false);
    CHECK(j["error"]["code"] == c.code);
    CHECK(j["error"]["message"].get<std::string>().size() > 10);
  }
  // A missing selected plugin is part of the listing's one object.
  const Run plugins = run_flipper("plugins --json --set planner.plugin=nope");
  INFO(plugins.out);
  CHECK(plugins.status == 2);
  json p;
  REQUIRE_NOTHROW(p = json::parse(plugins.out));
  CHECK(p["ok"] == false);
  CHECK(p["errors"][0]["code"] == "plugin_not_found");
}

TEST_CASE("a world for the other world plugin names the plugin that reads it", "[cli][world]") {
  const Run flat = run_flipper("run --set lexicon.path=:memory: --world " + kSrc +
                               "/configs/worlds/two-floors.json '{move up}'");
  INFO(flat.out);
  CHECK(flat.status == 2);
  CHECK(contains(flat.out,
                 "this is a 3-D world (its points have 3 coordinates), but world plugin "
                 "'grid2d' reads 2-D worlds: select octomap3d (--set "
                 "world.plugin=octomap3d)"));
  const Run deep = run_flipper("run --set lexicon.path=:memory: --config " + kSrc +
                               "/configs/octomap-astar.yaml --world " + kSrc +
                               "/configs/worlds/study2018.json '{move up}'");
  INFO(deep.out);
  CHECK(deep.status == 2);
  CHECK(contains(deep.out,
                 "this is a 2-D world (its points have 2 coordinates), but world "
                 "plugin 'octomap3d' reads 3-D worlds: select grid2d"));
}
