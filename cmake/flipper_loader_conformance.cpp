// The loader-layer conformance test of one plugin; flipper_add_conformance_test() compiles it
// with FLIPPER_CONFORMANCE_PLUGIN (name), FLIPPER_CONFORMANCE_PLUGIN_PATH (built .so) and
// FLIPPER_CONFORMANCE_PARAMS (the PARAMS given).
#include "flipper/testing/loader.hpp"
#include "flipper_conformance_driver.hpp"

TEST_CASE("loader conformance: " FLIPPER_CONFORMANCE_PLUGIN, "[conformance][loader]") {
  flipper::testing::check_loader_conformance(FLIPPER_CONFORMANCE_PLUGIN_PATH,
                                             flipper::testing::driver::params());
}
