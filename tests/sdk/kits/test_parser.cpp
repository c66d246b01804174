#include "trivial.hpp"
FLIPPER_PLUGIN(flipper::testplugins::TestParser, parser, "test_parser", "0.1.0",
               "kernel test parser")
