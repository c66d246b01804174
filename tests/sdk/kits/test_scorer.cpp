#include "trivial.hpp"
FLIPPER_PLUGIN(flipper::testplugins::TestScorer, scorer, "test_scorer", "0.1.0",
               "kernel test scorer")
