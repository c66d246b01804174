#include <catch2/catch.hpp>

#include "flipper/testing/world_conformance.hpp"
#include "space_worlds.hpp"

using namespace flipper;

FLIPPER_WORLD_CONFORMANCE(
    "octomap3d", [] { return testsupport::octomap_world(); }, testsupport::two_floors_json(),
    {{R"({"boxes": [{"min": [0, 0, 0], "max": [1, 1, 1]}], "robot": {"x": 0, "y": 0, "z": 0}})",
      "robot (0,0,0) collides"},
     {R"({"walls": [[0, 0]], "robot": {"x": 2, "y": 2, "z": 0}})", "walls[0]"},
     {R"({"robot": {"x": 2, "y": 2}})", "robot"}})
