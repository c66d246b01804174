// flipper's side of frontends.hpp: `serve`, `dds`, and `session`/`repl` with DDS services
// configured, exec flipper-frontends with the same arguments (same pid, same standard streams),
// which parses them again and runs the command with the network libraries loaded.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "dds_services.hpp"
#include "flipper/kernel/runtime.hpp"
#include "frontends.hpp"

namespace flipper::cli {
namespace {

char** g_argv = nullptr;

/// <exe>/../libexec/flipper-frontends: found relative to the executable only (the install
/// layout, which the build tree mirrors), like the plugins and configs.
std::string frontends_path() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path dir = ec ? std::filesystem::path(".") : exe.parent_path();
  return (dir / FLIPPER_FRONTENDS_RELATIVE).lexically_normal().string();
}

[[noreturn]] void exec_frontends() {
  const std::string path = frontends_path();
  const std::string cmd = g_argv != nullptr && g_argv[1] != nullptr ? g_argv[1] : "";
  std::cout.flush();
  std::fflush(nullptr);
  if (g_argv != nullptr && setenv(kFrontendsEnv, kFrontendsTag, 1) == 0)
    execv(path.c_str(), g_argv);
  const int err = errno;
  report_error(cmd, "frontend_missing",
               "cannot run the front-end program '" + path + "': " + std::strerror(err) +
                   " (`flipper " + cmd + "` runs there; it is installed with flipper)",
               kExitFailed);
  std::exit(kExitFailed);
}

}  // namespace

void enter(int /*argc*/, char** argv) {
  g_argv = argv;
}

int run_serve(const CommonOptions& /*opts*/) {
  exec_frontends();
}

int run_dds_node(const CommonOptions& /*opts*/) {
  exec_frontends();
}

int run_dds_security(const std::string& /*action*/, const DdsSecurityArgs& /*args*/) {
  exec_frontends();
}

int run_accounts(const CommonOptions& /*opts*/, const AccountsArgs& /*args*/) {
  exec_frontends();
}

DdsServices DdsServices::start(wiring::SessionHost& host, bool force_participant) {
  if (force_participant || wants_dds_services(host.runtime->config)) exec_frontends();
  return {};
}

std::unique_ptr<kernel::Session> DdsServices::open(const wiring::SessionHost& host) const {
  return host.open();
}

DdsServices::~DdsServices() = default;

}  // namespace flipper::cli
