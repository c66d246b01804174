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
FLIPPER_PLANNER_CONFORMANCE("ompl rrtstar", [] {
  return testsupport::load_plugin<sdk::Planner>(
      "ompl",
      sdk::Params({{"planner", std::string("rrtstar")}, {"iterations", std::int64_t{300}}}));
})
FLIPPER_PLANNER_CONFORMANCE("ompl prm", [] { return ompl("prm"); })
