// The parser kit (flipper/testing/parser_conformance.hpp) on the plugin under test: the core
// grammar (FLIPPER_CONFORMANCE_GRAMMAR, with the default config's words), core-language
// utterances, and the core bonus alone as the score (flipper/testing/core_scorer.hpp).
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "flipper/testing/core_scorer.hpp"
#include "flipper/testing/parser_conformance.hpp"
#include "flipper_conformance_driver.hpp"

TEST_CASE(FLIPPER_CONFORMANCE_PLUGIN ": parser conformance", "[conformance][parser]") {
  using namespace flipper;
  const auto parser = testing::driver::plugin<sdk::Parser>();
  parser->set_grammar(testing::driver::core_grammar());
  const testing::CoreScorer scorer;
  const std::vector<std::string> utterances{"move left",
                                            "visit world containing item is red ; pick item is red",
                                            "if possible move left ; move right",
                                            "repeat {3 - 1} times { pick item ; move left }",
                                            "foreach point in [[1,4],[3,4]] { visit point }",
                                            "visit room1 or room2 containing item",
                                            "pick every item has color red and has shape square"};
  testing::check_parser_conformance(*parser, scorer, utterances);
  // Two more instances, each with its own scorer, parse at once (flipper/sdk/plugin.hpp).
  const auto first = testing::driver::plugin<sdk::Parser>();
  const auto second = testing::driver::plugin<sdk::Parser>();
  first->set_grammar(testing::driver::core_grammar());
  second->set_grammar(testing::driver::core_grammar());
  const testing::CoreScorer second_scorer;
  testing::check_concurrent_parsers(*parser, *first, scorer, *second, second_scorer, utterances);
}
