// `flipper plugin new KIND NAME [DIR]` (apps/cli/plugin_new.cpp): the files of each kind with the
// examples' names replaced everywhere, and the refusals (exit 2). Building, testing and loading
// the scaffolds against an installed SDK is kernel.out_of_tree_plugin (tests/kernel).
#include <catch2/catch.hpp>
#include <filesystem>

#include "cli_test_support.hpp"

using namespace flipper::clitest;

namespace {

// The text with every run of white space (line breaks included) as one space.
std::string squeezed(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool space = c == ' ' || c == '\n';
    if (space && !out.empty() && out.back() == ' ') continue;
    out += space ? ' ' : c;
  }
  return out;
}

}  // namespace

TEST_CASE("plugin new writes each kind's CMakeLists, source, test and README, names replaced") {
  for (const std::string kind :
       {"world", "planner", "parser", "scorer", "rewriter", "similarity"}) {
    INFO(kind);
    const std::string dir = scratch_dir("new-" + kind) + "/fast_" + kind;
    const Run r = run_flipper("plugin new " + kind + " fast_" + kind + " " + dir);
    REQUIRE(r.status == 0);
    CHECK(contains(r.out, "created the " + kind + " plugin 'fast_" + kind + "'"));
    const std::string cmake = read_file(dir + "/CMakeLists.txt");
    CHECK(contains(cmake, "project(fast_" + kind + " LANGUAGES CXX)"));
    CHECK(contains(cmake, "enable_testing()"));
    CHECK(contains(cmake, "flipper_add_plugin(fast_" + kind + " KIND " + kind +
                              " VERSION 0.1.0 SOURCES fast_" + kind + ".cpp)"));
    CHECK(contains(cmake, "flipper_add_conformance_test(fast_" + kind + " SOURCES test_fast_" +
                              kind + ".cpp)"));
    CHECK(contains(cmake, "--set " + kind + ".plugin=fast_" + kind));
    const std::string source = read_file(dir + "/fast_" + kind + ".cpp");
    const std::string klass =
        "Fast" + std::string(1, static_cast<char>(kind[0] - 'a' + 'A')) + kind.substr(1);
    CHECK(contains(source, "namespace fast_" + kind + " {"));
    CHECK(contains(squeezed(source), "FLIPPER_PLUGIN(fast_" + kind + "::" + klass + ", " + kind +
                                         ", \"fast_" + kind + "\", FLIPPER_PLUGIN_VERSION"));
    CHECK(contains(source, "flipper/sdk/config_handles.hpp"));
    CHECK(contains(read_file(dir + "/test_fast_" + kind + ".cpp"), "load_plugin<"));
    CHECK(contains(read_file(dir + "/README.md"), "--set " + kind + ".plugin=fast_" + kind));
    // Nothing of the examples' names is left.
    for (const std::string& file :
         {cmake, source, read_file(dir + "/test_fast_" + kind + ".cpp")}) {
      CHECK_FALSE(contains(file, "bfs_example"));
      CHECK_FALSE(contains(file, "BfsExample"));
      CHECK_FALSE(contains(file, "example_" + kind));
      CHECK_FALSE(contains(file, "Example"));
    }
    CHECK(std::distance(std::filesystem::directory_iterator(dir),
                        std::filesystem::directory_iterator()) == 4);
  }
}

TEST_CASE("plugin new refuses a bad kind, a bad name and a folder that is not empty (exit 2)") {
  const std::string dir = scratch_dir("new-refused");
  Run r = run_flipper("plugin new robot fast " + dir + "/a");
  CHECK(r.status == 2);
  CHECK(contains(r.out, "flipper plugin new: [usage] kind: robot not in"));
  for (const std::string name : {"2fast", "Fast", "fa-st", "new", "namespace"}) {
    r = run_flipper("plugin new world " + name + " " + dir + "/b");
    CHECK(r.status == 2);
    CHECK(contains(r.out, "flipper plugin new: [bad_request] '" + name + "' is not a plugin name"));
  }
  // 64 characters are a name, 65 are not.
  CHECK(run_flipper("plugin new world a" + std::string(63, 'b') + " " + dir + "/c").status == 0);
  CHECK(run_flipper("plugin new world a" + std::string(64, 'b') + " " + dir + "/d").status == 2);
  r = run_flipper("plugin new world again " + dir + "/c");
  CHECK(r.status == 2);
  CHECK(contains(r.out, "exists and is not empty; choose another DIR"));
  CHECK_FALSE(std::filesystem::exists(dir + "/c/again.cpp"));
  // --config and --set are checked as for every command.
  r = run_flipper("plugin new world fine " + dir + "/e --set no.such=1");
  CHECK(r.status == 2);
  CHECK_FALSE(std::filesystem::exists(dir + "/e"));
}
