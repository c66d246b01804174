// The build-time commit script (cmake/FlipperBuildInfo.cmake) on trees of its own: without git
// everything is "unknown" and nothing fails; in a repository the commit is HEAD, and an edit to a
// tracked file makes the tree dirty. And this binary's own build information is filled in.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/record/build_info.hpp"

namespace fs = std::filesystem;

namespace {
std::string run(const std::string& cmd, int* status = nullptr) {
  std::string out;
  FILE* p = ::popen((cmd + " 2>/dev/null").c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[256];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  const int raw = ::pclose(p);
  if (status != nullptr) *status = raw;
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

std::string generate(const fs::path& source, const fs::path& output) {
  int status = 0;
  run("cmake -DSOURCE_DIR='" + source.string() + "' -DOUTPUT='" + output.string() + "' -P '" +
          FLIPPER_SOURCE_DIR + "/cmake/FlipperBuildInfo.cmake'",
      &status);
  CHECK(status == 0);
  std::ifstream in(output);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST_CASE("the commit is read at build time, a tree without git says unknown", "[record][build]") {
  const fs::path dir = fs::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "record" / "build-info";
  fs::remove_all(dir);
  fs::create_directories(dir / "tree");
  std::ofstream(dir / "tree" / "a.txt") << "one\n";
  const std::string plain = generate(dir / "tree", dir / "plain.cpp");
  CHECK_THAT(plain, Catch::Contains("kCommit = \"unknown\""));
  CHECK_THAT(plain, Catch::Contains("kDirty = \"unknown\""));

  int status = 0;
  run("git --version", &status);
  if (status != 0) return;  // no git on this machine: the case above is the one that applies
  const std::string git = "git -C '" + (dir / "tree").string() + "' ";
  run(git + "init -q && " + git + "add a.txt && " + git +
      "-c user.email=t@example.org -c user.name=t commit -q -m one");
  const std::string head = run(git + "rev-parse HEAD");
  REQUIRE(head.size() == 40);
  const std::string clean = generate(dir / "tree", dir / "clean.cpp");
  CHECK_THAT(clean, Catch::Contains("kCommit = \"" + head + "\""));
  CHECK_THAT(clean, Catch::Contains("kDirty = \"no\""));
  std::ofstream(dir / "tree" / "a.txt") << "two\n";
  const std::string dirty = generate(dir / "tree", dir / "dirty.cpp");
  CHECK_THAT(dirty, Catch::Contains("kCommit = \"" + head + "\""));
  CHECK_THAT(dirty, Catch::Contains("kDirty = \"yes\""));
  CHECK_THAT(dirty, Catch::Contains("-dirty\""));
}

TEST_CASE("this binary knows its versions and its commit", "[record][build]") {
  const auto& b = flipper::record::build_info();
  // The version the top-level CMakeLists.txt declares: `project(flipper VERSION x.y.z ...)`.
  std::ifstream lists(FLIPPER_SOURCE_DIR "/CMakeLists.txt");
  std::string version;
  for (std::string line; std::getline(lists, line) && version.empty();)
    if (line.rfind("project(flipper VERSION ", 0) == 0)
      version = line.substr(24, line.find(' ', 24) - 24);
  CHECK(b.version == version);
  CHECK(b.sdk.rfind("3.", 0) == 0);
  // A source tree that is a git checkout (a developer's clone, CI's fresh clone) must give the real
  // commit: HEAD, or an ancestor of it when commits were made after this binary was built. Only
  // a tree without git (a tarball) may say unknown.
  const std::string git = std::string("git -C '") + FLIPPER_SOURCE_DIR + "' ";
  int status = 0;
  const std::string top = run(git + "rev-parse --show-toplevel", &status);
  if (status == 0 && std::filesystem::equivalent(top, FLIPPER_SOURCE_DIR)) {
    INFO("the build says commit '" << b.commit << "', HEAD is " << run(git + "rev-parse HEAD"));
    REQUIRE(b.commit.size() == 40);
    CHECK(b.commit.find_first_not_of("0123456789abcdef") == std::string::npos);
    run(git + "merge-base --is-ancestor " + b.commit + " HEAD", &status);
    CHECK(status == 0);
    CHECK((b.dirty == "yes" || b.dirty == "no"));
  } else {
    CHECK((b.commit == "unknown" || b.commit.size() == 40));
    CHECK((b.dirty == "yes" || b.dirty == "no" || b.dirty == "unknown"));
  }
}
