// Stores that degrade instead of refusing (docs/naturalization.md §5 "Stores that degrade"): a
// lexicon store on a read-only file system, a read-only file (in a writable or a read-only
// folder), or a full device at start-up still serves its rules through `flipper session`;
// definitions and deletions are answered with lexicon_read_only / lexicon_full naming the file,
// accepts still move the robot, and the file is left as it was. Each condition is built for real: a
// read-only bind mount and a full tmpfs in a mount namespace of this test process (root with
// CAP_SYS_ADMIN, as CI runs), and file modes with the DAC-override capabilities dropped (so they
// bind root too).
#include <sched.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_test_support.hpp"
#include "naturalize_fixture.hpp"

namespace fs = std::filesystem;
using flipper::kernel::Json;
using flipper::naturalizetest::scratch_path;

namespace {

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct SessionRun {
  int status = -1;
  std::vector<Json> answers;  ///< the protocol answers, in order
  std::string other;          ///< everything else it printed (warnings, errors)
};

/// Runs `flipper session` on `store` with `lines` as its input, through `prefix` (e.g. setpriv).
SessionRun run_session(const std::string& store, const std::vector<std::string>& lines,
                       const std::string& prefix = "") {
  std::string input = "printf '%s\\n'";
  for (const auto& l : lines) input += " " + shell_quote(l);
  const auto r = flipper::clitest::run_shell(
      input + " | " + prefix + std::string(FLIPPER_BINARY_DIR) +
      "/bin/flipper session --set lexicon.path=" + shell_quote(store) + " 2>&1");
  SessionRun out;
  out.status = r.status;
  std::istringstream text(r.out);
  for (std::string line; std::getline(text, line);) {
    if (!line.empty() && line[0] == '{')
      out.answers.push_back(Json::parse(line));
    else
      out.other += line + "\n";
  }
  return out;
}

/// A store at `path` holding `go west` := `move left` (rule r1, by anonymous).
void make_store(const std::string& path) {
  const auto r = run_session(path, {R"({"op":"define","head":"go west","body":["move left"]})"});
  REQUIRE(r.status == 0);
  REQUIRE(r.answers.size() == 1);
  REQUIRE(r.answers[0].at("ok") == true);
}

/// The degraded store serves its rule, refuses writes with `code` naming the file, accepts, and
/// changes nothing in the file.
void check_degraded(const std::string& store, const std::string& code, const std::string& state,
                    const std::string& prefix = "") {
  const std::string before = slurp(store);
  const auto r = run_session(store,
                             {
                                 R"({"op":"query","text":"go west"})",
                                 R"({"op":"accept","rank":0})",
                                 R"({"op":"define","head":"go east","body":["move right"]})",
                                 R"({"op":"delete_rule","rule":"r1"})",
                                 R"({"op":"rules"})",
                             },
                             prefix);
  INFO("output besides answers:\n" << r.other);
  CHECK(r.status == 0);
  REQUIRE(r.answers.size() == 5);
  CHECK(r.answers[0].at("status") == "induced");
  CHECK(r.answers[1].at("ok") == true);  // the robot moves; what it taught is kept in memory
  for (int i : {2, 3}) {
    INFO(r.answers[static_cast<std::size_t>(i)].dump());
    CHECK(r.answers[static_cast<std::size_t>(i)].at("ok") == false);
    CHECK(r.answers[static_cast<std::size_t>(i)].at("error").at("code") == code);
    CHECK_THAT(r.answers[static_cast<std::size_t>(i)].at("error").at("message").get<std::string>(),
               Catch::Contains(store) && Catch::Contains(state));
  }
  REQUIRE(r.answers[4].at("rules").size() == 1);
  CHECK(r.answers[4].at("rules")[0].at("id") == "r1");
  CHECK_THAT(r.other, Catch::Contains("lexicon store '" + store + "' is " + state +
                                      ": it serves its 1 rule;"));
  CHECK(slurp(store) == before);
  // `flipper lexicon list` reads it too.
  const auto list = flipper::clitest::run_shell(
      prefix + std::string(FLIPPER_BINARY_DIR) +
      "/bin/flipper lexicon list --set lexicon.path=" + shell_quote(store) + " 2>&1");
  CHECK(list.status == 0);
  CHECK_THAT(list.out, Catch::Contains("1 rule in " + store));
}

/// Mounts made here live in a mount namespace of this process (and the flipper it starts): they
/// vanish with it, whatever happens. Empty when that is possible, else why not.
std::string private_mounts() {
  if (::geteuid() != 0) return "not root";
  if (::unshare(CLONE_NEWNS) != 0)
    return std::string("unshare(CLONE_NEWNS): ") + std::strerror(errno);
  if (::mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
    return std::string("making / private: ") + std::strerror(errno);
  return "";
}

std::string fresh_dir(const std::string& stem) {
  const std::string dir = scratch_path(stem);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("a store on a read-only file system serves its rules", "[naturalize][degraded]") {
  const std::string why = private_mounts();
  if (!why.empty()) {
    WARN("skipped: a read-only bind mount needs root with CAP_SYS_ADMIN ("
         << why << "); the read-only folder case below covers the file-mode variant");
    return;
  }
  const std::string dir = fresh_dir("ro-fs");
  const std::string mnt = fresh_dir("ro-fs-mnt");
  make_store(dir + "/lexicon.sqlite");
  REQUIRE(::mount(dir.c_str(), mnt.c_str(), nullptr, MS_BIND, nullptr) == 0);
  REQUIRE(::mount(nullptr, mnt.c_str(), nullptr, MS_REMOUNT | MS_BIND | MS_RDONLY, nullptr) == 0);
  // Really read-only, even for root.
  CHECK_FALSE(std::ofstream(mnt + "/probe").good());
  check_degraded(mnt + "/lexicon.sqlite", "lexicon_read_only", "read-only");
  CHECK(::umount2(mnt.c_str(), MNT_DETACH) == 0);
}

/// Root passes file modes by its DAC-override capabilities: a session run through this prefix runs
/// without them (dropped from the bounding set, so exec cannot give them back), as root still, so
/// every other path works.
std::string without_dac_override() {
  return ::geteuid() == 0 ? "setpriv --bounding-set=-dac_override,-dac_read_search,-fowner -- "
                          : "";
}

TEST_CASE("a read-only store file in a writable folder serves its rules",
          "[naturalize][degraded]") {
  const std::string dir = fresh_dir("ro-file");
  const std::string store = dir + "/lexicon.sqlite";
  make_store(store);
  fs::permissions(store, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  check_degraded(store, "lexicon_read_only", "read-only", without_dac_override());
  fs::permissions(store, fs::perms::owner_read | fs::perms::owner_write);
}

TEST_CASE("a read-only store file in a read-only folder serves its rules",
          "[naturalize][degraded]") {
  const std::string dir = fresh_dir("ro-dir");
  const std::string store = dir + "/lexicon.sqlite";
  make_store(store);
  fs::permissions(store, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                           fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const std::string prefix = without_dac_override();
  if (!prefix.empty()) {
    const auto probe = flipper::clitest::run_shell(prefix + "sh -c " +
                                                   shell_quote(": > " + dir + "/probe") + " 2>&1");
    REQUIRE(probe.status != 0);  // the folder's mode binds the session
  }
  check_degraded(store, "lexicon_read_only", "read-only", prefix);
  fs::permissions(dir, fs::perms::owner_all);
  fs::permissions(store, fs::perms::owner_read | fs::perms::owner_write);
}

TEST_CASE("a store on a full device at start-up serves its rules", "[naturalize][degraded]") {
  const std::string why = private_mounts();
  if (!why.empty()) {
    WARN(
        "skipped: a small tmpfs needs root with CAP_SYS_ADMIN ("
        << why
        << "); a full store is also simulated with max_page_count in tests/naturalization/lexicon");
    return;
  }
  const std::string mnt = fresh_dir("full-mnt");
  REQUIRE(::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") == 0);
  const std::string store = mnt + "/lexicon.sqlite";
  make_store(store);
  {
    // Fill the device: writes fail with ENOSPC from here on.
    std::ofstream fill(mnt + "/fill", std::ios::binary);
    const std::string block(4096, 'x');
    for (int i = 0; i < 1024 && fill.write(block.data(), block.size()); ++i) fill.flush();
  }
  CHECK_FALSE(std::ofstream(mnt + "/probe").write("x", 1).flush().good());
  check_degraded(store, "lexicon_full", "full");
  // With room again, the same store takes definitions.
  fs::remove(mnt + "/fill");
  fs::remove(mnt + "/probe");
  const auto r = run_session(store, {R"({"op":"define","head":"go east","body":["move right"]})"});
  REQUIRE(r.answers.size() == 1);
  CHECK(r.answers[0].at("ok") == true);
  CHECK(::umount2(mnt.c_str(), MNT_DETACH) == 0);
}
