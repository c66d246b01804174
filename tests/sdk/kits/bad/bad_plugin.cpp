// One source, many broken plugins: BAD_VARIANT selects what is wrong (see CMakeLists.txt).
// Each is the trivial test planner with exactly one defect the kernel must catch cleanly.
#include "trivial.hpp"

#ifndef BAD_NAME
#define BAD_NAME "bad"
#endif

#if defined(BAD_ABI)  // a plugin from a future ABI
#undef FLIPPER_PLUGIN_ABI
#define FLIPPER_PLUGIN_ABI 4
#elif defined(BAD_SDK_MAJOR)  // built against SDK 4.x
#undef FLIPPER_SDK_VERSION_MAJOR
#define FLIPPER_SDK_VERSION_MAJOR 4
#elif defined(BAD_SDK_MINOR)  // built against a newer SDK minor than the kernel's
#undef FLIPPER_SDK_VERSION_MINOR
#define FLIPPER_SDK_VERSION_MINOR 99
#elif defined(BAD_FINGERPRINT)  // libstdc++'s old string ABI
#undef FLIPPER_BUILD_FINGERPRINT
#define FLIPPER_BUILD_FINGERPRINT "abi=3;libstdc++;cxx11abi=0;ptrsize=8"
#endif

namespace {
class Throwing : public flipper::testplugins::TestPlanner {
 public:
  explicit Throwing(const flipper::sdk::Params& p) : TestPlanner(p) {
    throw std::runtime_error("cannot open the planner database");
  }
};
}  // namespace

#if defined(BAD_NO_DESCRIPTOR)
// A shared library that is not a Flipper plugin at all.
extern "C" FLIPPER_PLUGIN_EXPORT int not_a_flipper_plugin() {
  return 42;
}
#elif defined(BAD_SIZE)
// A descriptor layout that differs from the kernel's (as if a field had been added).
extern "C" FLIPPER_PLUGIN_EXPORT const FlipperPluginDescriptor* flipper_plugin_entry(
    const FlipperHandshake*, FlipperHandshake* plugin) {
  if (plugin != nullptr)
    *plugin = {FLIPPER_PLUGIN_ABI, static_cast<std::uint32_t>(sizeof(FlipperPluginDescriptor) + 8),
               static_cast<std::uint32_t>(alignof(FlipperPluginDescriptor))};
  return nullptr;
}
#elif defined(BAD_THROWS)
FLIPPER_PLUGIN(Throwing, planner, BAD_NAME, "0.1.0", "constructor throws")
#else
FLIPPER_PLUGIN(flipper::testplugins::TestPlanner, planner, BAD_NAME, "0.1.0", "broken on purpose")
#endif
