#pragma once
// Runs build/bin/flipper like a user (through the shell) and gives back status and output.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace flipper::clitest {

struct Run {
  int status = -1;
  std::string out;  ///< stdout, then stderr when `merge` (the default)
};

/// Runs a shell command line as written (redirections included); its stdout and exit status.
inline Run run_shell(const std::string& cmd) {
  Run r;
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.out += buf.data();
  const int raw = ::pclose(p);
  REQUIRE(WIFEXITED(raw));  // never killed by a signal
  r.status = WEXITSTATUS(raw);
  return r;
}

/// `flipper ARGS` through the shell: `merge` puts its stderr after its stdout in `out`; otherwise
/// its stderr goes to the test's own (ctest shows it beside a failure: a sanitizer's report of a
/// child that died before writing its answer, say), never to `out`.
inline Run run_flipper(const std::string& args, bool merge = true) {
  return run_shell(std::string(FLIPPER_BINARY_DIR) + "/bin/flipper " + args +
                   (merge ? " 2>&1" : ""));
}

/// A fresh path under build/tests/tmp/cli (any old file removed).
inline std::string scratch(const std::string& name) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "cli";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
  return path.string();
}

/// A fresh, empty directory under build/tests/tmp/cli.
inline std::string scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "cli" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = scratch(name);
  std::ofstream(path) << text;
  return path;
}

/// write_file under a name of this process's own (its pid before the extension of `name`): for a
/// helper that several test cases of one file call, which ctest runs as processes side by side
/// (with one shared name, one case rewrites the file while another's command reads it).
inline std::string write_own_file(const std::string& name, const std::string& text) {
  const auto dot = name.rfind('.');
  const std::string pid = "-" + std::to_string(::getpid());
  return write_file(
      dot == std::string::npos ? name + pid : name.substr(0, dot) + pid + name.substr(dot), text);
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline bool contains(const std::string& text, const std::string& word) {
  return text.find(word) != std::string::npos;
}

}  // namespace flipper::clitest
