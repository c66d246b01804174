// flipper-frontends' side of frontends.hpp: run only under the tag of the flipper that execs it.
// Run directly (no tag), it is the whole of flipper, which helps debugging.
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common.hpp"
#include "frontends.hpp"

namespace flipper::cli {

void enter(int argc, char** argv) {
  const char* tag = std::getenv(kFrontendsEnv);
  if (tag == nullptr) return;
  if (std::string(tag) != kFrontendsTag) {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    report_error(argc > 1 ? argv[1] : "", "frontend_mismatch",
                 "the front-end program '" + self + "' is '" + kFrontendsTag +
                     "' but was started by '" + tag + "' (a mixed install; reinstall flipper)",
                 kExitFailed);
    std::exit(kExitFailed);
  }
  unsetenv(kFrontendsEnv);  // not inherited by anything this process starts
}

}  // namespace flipper::cli
