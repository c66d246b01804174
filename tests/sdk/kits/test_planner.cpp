#include "trivial.hpp"
FLIPPER_PLUGIN(flipper::testplugins::TestPlanner, planner, "test_planner", "0.1.0",
               "kernel test planner")
