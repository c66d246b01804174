// `flipper dds` exits within a bounded time after SIGTERM, whatever its Cyclone configuration.
// With a user config that turns multicast on for `lo` (accepted by the loopback check), Cyclone's
// participant deletion waited forever for its multicast receive thread: the node printed
// "stopped" and never exited (gdb: dds_delete -> join_thread on "recvMC", blocked in recvmsg).
// The node now bounds its teardown (apps/cli/dds_run.cpp, docs/ros2.md).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "dds_test_support.hpp"

using namespace flipper::ddstest;

namespace {

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `flipper dds --config <config> --set dds.domain=<domain>`, its stderr into `log`.
pid_t start_node(const std::filesystem::path& config, int domain,
                 const std::filesystem::path& log) {
  std::vector<std::string> args = {flipper_bin(), "dds",
                                   "--config",    config.string(),
                                   "--set",       "dds.domain=" + std::to_string(domain)};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    if (std::freopen(log_path.c_str(), "w", stderr) == nullptr) _exit(126);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

}  // namespace

TEST_CASE("flipper dds exits soon after SIGTERM, multicast on lo included", "[dds][exit]") {
  const int domain = test_domain();
  const auto dir = scratch_dir("exit");
  const std::string base = std::string(FLIPPER_SOURCE_DIR) + "/configs/default.yaml";
  const std::vector<std::pair<std::string, std::string>> configs = {
      {"loopback", "extends: " + base + "\n"},
      {"multicast-on-lo",
       "extends: " + base +
           "\ndds:\n  interfaces: [lo]\n  config: |\n    <CycloneDDS><Domain Id=\"any\"><General>"
           "<Interfaces><NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>"
           "<AllowMulticast>true</AllowMulticast></General></Domain></CycloneDDS>\n"}};
  for (const auto& [name, text] : configs) {
    INFO(name);
    const auto config = dir / (name + ".yaml");
    std::ofstream(config) << text;
    const auto log = dir / (name + ".log");
    const pid_t pid = start_node(config, domain, log);
    const bool serving =
        wait_until([&] { return read_text(log).find("serving") != std::string::npos; },
                   std::chrono::seconds(60));
    kill(pid, SIGTERM);
    int status = 0;
    // The node's own limit is 5 s; 30 s only stops a runaway test.
    const bool exited =
        wait_until([&] { return waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30));
    if (!exited) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
    INFO(read_text(log));
    REQUIRE(serving);
    REQUIRE(exited);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    REQUIRE(read_text(log).find("flipper dds: stopped after 0 answers") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}
