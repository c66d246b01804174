// scripts/replay-dev as a user runs it: it reuses the build tree (no second tree built silently),
// says what it builds, shows the replay's progress and writes where it says.
#include <sys/wait.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

TEST_CASE("scripts/replay-dev reuses the build tree and shows progress", "[scripts]") {
  const fs::path out = fs::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "replay-dev";
  fs::remove_all(out);
  const std::string cmd = "FLIPPER_BUILD='" + std::string(FLIPPER_BINARY_DIR) +
                          "' FLIPPER_REPLAY_OUT='" + out.string() + "' sh '" +
                          std::string(FLIPPER_SOURCE_DIR) +
                          "/scripts/replay-dev' --runs sep2018/TuesdayAfternoon --max-queries 3 "
                          "2>&1 < /dev/null";
  std::string text;
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) text += buf.data();
  const int raw = ::pclose(p);
  INFO(text);
  REQUIRE(WIFEXITED(raw));
  CHECK(WEXITSTATUS(raw) == 0);
  CHECK_THAT(text, Catch::Contains("replay-dev: building flipper and the default plugins in " +
                                   std::string(FLIPPER_BINARY_DIR) + " (incremental)"));
  // The replay's progress (plain lines when not on a terminal), then the headline figures.
  CHECK_THAT(text, Catch::Contains("replay plain: 25% (1/4) sep2018/TuesdayAfternoon"));
  CHECK_THAT(text, Catch::Contains("replay plain: 100% (4/4) sep2018/TuesdayAfternoon"));
  CHECK_THAT(text, Catch::Contains("### Status agreement"));
  // A new run folder under FLIPPER_REPLAY_OUT, and the report in it.
  CHECK_THAT(text, Catch::Contains("run: " + out.string() + "/dev-replay-"));
  CHECK_THAT(text, Catch::Contains("report: " + out.string() + "/dev-replay-"));
  CHECK(fs::exists(out / "latest" / "report.md"));
  // The default is the setup's build/, not a second tree.
  CHECK_FALSE(fs::exists(fs::path(FLIPPER_SOURCE_DIR) / "build-replay" / "CMakeCache.txt"));
}
