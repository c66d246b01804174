#include "trivial.hpp"
FLIPPER_PLUGIN(flipper::testplugins::TestWorld, world, "test_world", "0.1.0", "kernel test world")
