#include <catch2/catch.hpp>

#include "flipper/testing/planner_conformance.hpp"
#include "plugin_fixture.hpp"

using namespace flipper;

namespace {
std::shared_ptr<sdk::Planner> ompl(const std::string& planner) {
  return testsupport::load_plugin<sdk::Planner>("ompl", sdk::Params({{"planner", planner}}));
}
}  // namespace

FLIPPER_PLANNER_CONFORMANCE("ompl rrtconnect", [] { return ompl("rrtconnect"); })
FLIPPER_PLANNER_CONFORMANCE("ompl rrt", [] { return ompl("rrt"); })
// rrtstar with max_iterations 20,000 (default 100,000): a request without a path spends the whole
// budget, and RRT*'s rewiring makes its late iterations the dearest (30.5 s of CPU for this case
// in Release at 100,000, 3.3 s at 20,000); the kit's reachable requests are all found at 20,000
// (48/48, 49/49, 58/58, 52/52; it requires 90 %), and rrt and rrtconnect keep the default.
FLIPPER_PLANNER_CONFORMANCE("ompl rrtstar", [] {
  return testsupport::load_plugin<sdk::Planner>(
      "ompl", sdk::Params({{"planner", std::string("rrtstar")},
                           {"iterations", std::int64_t{300}},
                           {"max_iterations", std::int64_t{20000}}}));
})
FLIPPER_PLANNER_CONFORMANCE("ompl prm", [] { return ompl("prm"); })
