// The build information: versions from the build, commit from the generated file
// (cmake/FlipperBuildInfo.cmake writes build_info_generated.cpp at every build).
#include "flipper/record/build_info.hpp"

#include "flipper/sdk/version.hpp"

namespace flipper::record {
namespace generated {
extern const char* const kCommit;
extern const char* const kDescribe;
extern const char* const kDirty;
}  // namespace generated

const BuildInfo& build_info() {
  static const BuildInfo info{FLIPPER_RECORD_VERSION,
                              std::to_string(FLIPPER_SDK_VERSION_MAJOR) + "." +
                                  std::to_string(FLIPPER_SDK_VERSION_MINOR) + "." +
                                  std::to_string(FLIPPER_SDK_VERSION_PATCH),
                              generated::kCommit, generated::kDescribe, generated::kDirty};
  return info;
}

}  // namespace flipper::record
