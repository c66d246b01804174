// The commands of the README and the docs run as written and print what the pages say they do.
//
// Which commands: every line of a fenced code block that directly follows the marker line
// `<!-- readme-test -->` in README.md, then in the pages of docs/ in name order (text after "  # "
// is the page's comment, not part of the command). Blocks without the marker are not run, so a new
// section does not break this test by accident; marking a block makes each of its commands need an
// entry in kExpected below.
// The commands run in order, in one scratch directory that looks like the repository root
// (build/, configs/, examples/, docs/ linked), with HOME there too, so files they write and the
// default lexicon stay out of the tree.
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Expected {
  int status;
  std::vector<std::string> output;  ///< substrings of stdout+stderr, each required
};

// One entry per marked command of the README and docs/ (exact text).
const std::map<std::string, Expected> kExpected = {
    // Your first ten minutes. room1 is x 9..11, y 0..2; its nearest cell by path from [2,4] is
    // [9,0], 13 moves: down the x=1 corridor to y=0 (5), then right along y=0 to x=9 (8).
    {R"(build/bin/flipper run "visit room1")",
     {0, {"interpretation: {visit room1}", "trace (13 steps):", "robot: [9,0]"}}},
    {R"(printf "visit room3 or room5 containing item is red\n2\n" | build/bin/flipper repl)",
     {0, {"2 of 2 shown. Choose 1..2, or r", "Done: 5 steps.", "Robot at [7,4]"}}},
    {R"(printf "zig zag\n:define\nmove up\nmove right\n\nzig zag\n1\n" | build/bin/flipper repl)",
     {0,
      {"I did not understand that.",
       "Learned 1 rule:", "$Action -> zig zag  =>  {{move up};{move right}}",
       "[1] {{move up};{move right}}", "Done: 2 steps.", "Robot at [3,5]"}}},
    {R"(build/bin/flipper run --set planner.plugin=ompl "visit room1")",
     {0, {"interpretation: {visit room1}", "realizable: yes", "robot: [9,"}}},
    {R"(build/bin/flipper replay --experiment configs/experiments/dev-replay.yaml --out out/first-replay)",
     {0,
      {"plain: status agreement ", "/3950, accepts matched ", "/807",
       "run: out/first-replay/dev-replay-", "report: out/first-replay/dev-replay-"}}},

    // Using it (docs/usage.md)
    {R"(build/bin/flipper run "visit world containing item is red; pick item is red")",
     // The nearest red item from [2,4] is the red circle 5 cells right at [7,4] (the red
     // triangle at [4,0] is 6+ away around the wall at [2,2]).
     {0,
      {"interpretation: {{visit {world containing item {is red}}};{pick item {is red}}}",
       "trace (6 steps):", "  pick [7,4] red circle", "realizable: yes",
       "robot: [7,4], holding 1: red circle"}}},
    {R"(build/bin/flipper run --json --world configs/worlds/study2018.json "{move up}")",
     {0, {R"("ok":true)", R"("formula":"{move up}")", R"("trace":[{"act":"move","to":[2,5]}])"}}},
    // The 3-D world: the yellow circle lies on the top floor (z=2), reached through the one
    // passage in the ceiling at [8,1,1] (configs/worlds/two-floors.json).
    {R"(build/bin/flipper run --config configs/octomap-ompl.yaml "visit world containing item is yellow; pick item is yellow")",
     {0,
      {"  move [8,1,1]\n", "  pick [8,6,2] yellow circle", "realizable: yes",
       "robot: [8,6,2], holding 1: yellow circle"}}},
    {R"(build/bin/flipper session examples/session.jsonl)",
     // r2: "zig zag" of the ten-minute walkthrough above is r1 in the same (HOME) store.
     {0,
      {R"({"ok":true,"op":"define","rules":[{"id":"r2")",
       R"({"ok":true,"op":"query","status":"induced")", R"({"ok":true,"op":"accept")"}}},
    {R"(build/bin/flipper repl < /dev/null)", {0, {"Legend:", "Robot at [2,4]", "bye"}}},
    {R"(build/bin/flipper replay --experiment configs/experiments/dev-replay.yaml --max-queries 5 --out out/replay-dev)",
     {0, {"plain: status agreement ", "report: out/replay-dev/dev-replay-"}}},
    {R"(build/bin/flipper plugins)", {0, {"* astar", "* grid2d", "STATUS"}}},
    {R"(build/bin/flipper plugins --params)", {0, {"astar (planner", "heuristic"}}},
    {R"(build/bin/flipper plugins astar)", {0, {"astar (planner", "max_expansions"}}},
    {R"(build/bin/flipper lexicon list --author ana)",
     {0,
      {"r2  ana ", "$Action -> pick $Number items => {repeat $1 times {pick item }}",
       "home/.local/share/flipper/lexicon.sqlite"}}},
    {R"(build/bin/flipper lexicon export lexicon.jsonl)",
     {0, {"exported 2 definitions and 3 rules", "to lexicon.jsonl"}}},
    {R"(build/bin/flipper lexicon import lexicon.jsonl --set lexicon.path=other.sqlite)",
     {0, {"imported 2 definitions (3 rules induced)", "into ", "/other.sqlite"}}},
    {R"(build/bin/flipper lexicon delete r1 --user bob)",
     {1, {"flipper lexicon delete: [forbidden] "}}},
    {R"(build/bin/flipper config check configs/grid-ompl.yaml)",
     {0, {"config ok: configs/grid-ompl.yaml", "plugin: ompl"}}},
    {R"(build/bin/flipper --version)", {0, {"flipper 0.1.0 (plugin SDK 3."}}},
};

std::vector<std::string> marked_commands(const std::string& readme_path) {
  std::ifstream in(readme_path);
  REQUIRE(in.good());
  std::vector<std::string> out;
  bool marked = false, inside = false;
  for (std::string line; std::getline(in, line);) {
    if (!inside && line.rfind("<!-- readme-test -->", 0) == 0) {
      marked = true;
      continue;
    }
    if (line.rfind("```", 0) == 0) {
      inside = !inside && marked;
      if (!inside) marked = false;
      continue;
    }
    marked = marked && line.empty();  // the marker applies to the very next block
    if (!inside) continue;
    const auto comment = line.find("  # ");
    std::string cmd = line.substr(0, comment);
    while (!cmd.empty() && cmd.back() == ' ') cmd.pop_back();
    if (!cmd.empty()) out.push_back(cmd);
  }
  return out;
}

struct Result {
  int status = -1;
  std::string out;
};

Result run_in(const fs::path& dir, const std::string& command) {
  const std::string sh = "cd '" + dir.string() + "' && HOME='" + dir.string() +
                         "/home' FLIPPER_HISTORY= sh -c '" + command + "' 2>&1 < /dev/null";
  // Commands contain double quotes but no single quotes (checked below).
  Result r;
  FILE* p = ::popen(sh.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.out += buf.data();
  const int raw = ::pclose(p);
  REQUIRE(WIFEXITED(raw));
  r.status = WEXITSTATUS(raw);
  return r;
}

// README.md, then every page of docs/ in name order: the order the commands run in.
std::vector<std::string> marked_commands_of_pages(const fs::path& src) {
  std::vector<fs::path> docs;
  for (const auto& e : fs::directory_iterator(src / "docs"))
    if (e.path().extension() == ".md") docs.push_back(e.path());
  std::sort(docs.begin(), docs.end());
  std::vector<std::string> out = marked_commands((src / "README.md").string());
  for (const auto& page : docs) {
    auto more = marked_commands(page.string());
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

}  // namespace

TEST_CASE("every command of the README's marked blocks runs and prints what it should",
          "[readme]") {
  const fs::path src = FLIPPER_SOURCE_DIR;
  const auto commands = marked_commands_of_pages(src);
  REQUIRE(commands.size() >= kExpected.size());

  const fs::path dir = fs::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "readme";
  fs::remove_all(dir);
  fs::create_directories(dir / "home");
  fs::create_directory_symlink(FLIPPER_BINARY_DIR, dir / "build");
  for (const char* d : {"configs", "examples", "docs"})
    fs::create_directory_symlink(src / d, dir / d);

  for (const auto& cmd : commands) {
    INFO("README/docs command: " << cmd);
    const auto it = kExpected.find(cmd);
    if (it == kExpected.end())
      FAIL(
          "command in a <!-- readme-test --> block has no expected output in "
          "tests/readme/test_readme_commands.cpp: "
          << cmd);
    REQUIRE(cmd.find('\'') == std::string::npos);
    const Result r = run_in(dir, cmd);
    INFO("output:\n" << r.out);
    CHECK(r.status == it->second.status);
    for (const auto& want : it->second.output) CHECK_THAT(r.out, Catch::Contains(want));
  }
  // Item 9 of the path rule: `--set lexicon.path=other.sqlite` wrote into the current directory.
  CHECK(fs::exists(dir / "other.sqlite"));
  // The run's own folder under --out, reached through the `latest` link.
  CHECK(fs::exists(dir / "out" / "first-replay" / "latest" / "report.md"));
  CHECK(fs::exists(dir / "out" / "first-replay" / "latest" / "manifest.json"));
  CHECK_FALSE(fs::exists(src / "configs" / "other.sqlite"));
  // No stale expectations: each entry is a README command.
  for (const auto& [cmd, expected] : kExpected) {
    INFO("expected output listed for a command the README's marked blocks no longer have: " << cmd);
    CHECK(std::find(commands.begin(), commands.end(), cmd) != commands.end());
  }
}
