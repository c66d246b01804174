#pragma once
// The children of a process as Linux lists them, for tests of who forks and reaps what.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace flipper::testsupport {

/// The pids of the children of process `pid`, ended (not yet reaped) or not:
/// /proc/PID/task/*/children.
inline std::vector<int> children_of(int pid) {
  std::vector<int> out;
  for (const auto& task :
       std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    std::ifstream f(task.path() / "children");
    for (int c = 0; f >> c;) out.push_back(c);
  }
  return out;
}

}  // namespace flipper::testsupport
