// The scorer kit (flipper/testing/scorer_conformance.hpp) on the plugin under test: fresh
// instances, the toolkit's chart parser over the core grammar (FLIPPER_CONFORMANCE_GRAMMAR) and
// an utterance with several readings.
#include <catch2/catch.hpp>

#include "flipper/testing/scorer_conformance.hpp"
#include "flipper/toolkit/chart_parser.hpp"
#include "flipper_conformance_driver.hpp"

TEST_CASE(FLIPPER_CONFORMANCE_PLUGIN ": scorer conformance", "[conformance][scorer]") {
  using namespace flipper;
  toolkit::ChartParser parser;
  parser.set_grammar(testing::driver::core_grammar());
  testing::check_scorer_conformance([] { return testing::driver::plugin<sdk::Scorer>(); }, parser,
                                    "visit room1 or room2 containing item is red or is blue");
}
