// bench_crowd [--flipper BIN] [--defines N] [USERS...]: N `flipper session` processes on one
// lexicon file (default 10, 50, 100 users x 10 defines), each defining, querying, accepting and
// deleting (tests/support/crowd.hpp). Prints lost acknowledged rules, errors users saw, cross-
// process visibility failures, wrong deletions, integrity, defines/s and define latency p50/p99.
// Targets: 0 lost, 0 errors, 0 cross failures, 0 wrong deletions, integrity ok.
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "crowd.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  std::string flipper = "build/bin/flipper";
  int defines = 10;
  std::vector<int> crowds;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--flipper") && i + 1 < argc)
      flipper = argv[++i];
    else if (!std::strcmp(argv[i], "--defines") && i + 1 < argc)
      defines = std::stoi(argv[++i]);
    else
      crowds.push_back(std::stoi(argv[i]));
  }
  if (crowds.empty()) crowds = {10, 50, 100};
  const fs::path dir =
      fs::temp_directory_path() / ("flipper-bench-crowd-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::printf("%6s %8s %8s %6s %7s %8s %8s %10s %10s %10s %10s\n", "users", "defines", "acked",
              "lost", "errors", "x-fail", "wrongdel", "integrity", "defines/s", "p50 ms", "p99 ms");
  int bad = 0;
  for (int users : crowds) {
    flipper::testsupport::CrowdOptions o;
    o.flipper = flipper;
    o.store = (dir / ("crowd-" + std::to_string(users) + ".sqlite")).string();
    o.users = users;
    o.defines = defines;
    const auto r = flipper::testsupport::run_crowd(o);
    const double rate = r.seconds > 0 ? static_cast<double>(r.define_ms.size()) / r.seconds : 0;
    std::printf("%6d %8zu %8ld %6ld %7ld %8ld %8ld %10s %10.1f %10.1f %10.1f\n", users,
                r.define_ms.size(), r.acknowledged_rules, r.lost, r.errors, r.cross_failures,
                r.wrong_deletions + r.foreign_deletes, r.integrity.c_str(), rate, r.percentile(0.5),
                r.percentile(0.99));
    for (const auto& e : r.error_samples) std::printf("    error: %.300s\n", e.c_str());
    bad += r.lost || r.errors || r.cross_failures || r.wrong_deletions || r.foreign_deletes ||
           r.integrity != "ok";
  }
  std::printf(
      "targets: lost 0, errors 0, x-fail (cross-process visibility) 0, wrongdel 0, "
      "integrity ok -> %s\n",
      bad ? "MISSED" : "met");
  fs::remove_all(dir);
  return 0;
}
