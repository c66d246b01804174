#include <catch2/catch.hpp>

#include "flipper/testing/world_conformance.hpp"
#include "plugin_fixture.hpp"
#include "study_world.hpp"

using namespace flipper;

FLIPPER_WORLD_CONFORMANCE(
    "grid2d", [] { return testsupport::load_plugin<sdk::World>("grid2d"); },
    testsupport::study_world_json(),
    {{R"({"walls": [[2, 6]], "robot": {"x": 2, "y": 6}})", "robot (2,6) is on a wall"},
     {R"({"walls": [[0, 0, 0]], "robot": {"x": 2, "y": 6}})", "walls[0]: a point must be"}})
