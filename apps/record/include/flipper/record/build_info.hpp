#pragma once
/// @file build_info.hpp
/// What this flipper binary is: its version, the plugin SDK version it was built with, and the
/// source commit and whether the tree had uncommitted changes, read by `git` when the binary was
/// built (cmake/FlipperBuildInfo.cmake; "unknown" for a tree without git). A run's manifest
/// records it (docs/experiments.md §2).

#include <string>

namespace flipper::record {

struct BuildInfo {
  std::string version;   ///< flipper's own version ("0.1.0")
  std::string sdk;       ///< the plugin SDK version ("2.1.0")
  std::string commit;    ///< full commit id, or "unknown"
  std::string describe;  ///< `git describe --always --dirty`, or "unknown"
  std::string dirty;     ///< "yes", "no" or "unknown"
};

/// This binary's build information.
const BuildInfo& build_info();

}  // namespace flipper::record
