// The parser kit (flipper/testing/parser_conformance.hpp) on the plugin under test: the core
// grammar (FLIPPER_CONFORMANCE_GRAMMAR, with the default config's words), core-language
// utterances, and a scorer that gives each node the core bonus of docs/naturalization.md §3 alone
// (what every scorer gives before it learns).
#include <catch2/catch.hpp>

#include "flipper/testing/parser_conformance.hpp"
#include "flipper/toolkit/linear_scorer.hpp"
#include "flipper_conformance_driver.hpp"

namespace {

class UntrainedScorer : public flipper::toolkit::LinearScorer {
 public:
  UntrainedScorer() : LinearScorer(false, {"untrained", "untrained", ""}) {}

 protected:
  void update(const std::vector<flipper::sdk::Candidate>&, std::size_t,
              const flipper::sdk::ScoreContext&) override {}
};

}  // namespace

TEST_CASE(FLIPPER_CONFORMANCE_PLUGIN ": parser conformance", "[conformance][parser]") {
  using namespace flipper;
  const auto parser = testing::driver::plugin<sdk::Parser>();
  parser->set_grammar(testing::driver::core_grammar());
  const UntrainedScorer scorer;
  testing::check_parser_conformance(
      *parser, scorer,
      {"move left", "visit world containing item is red ; pick item is red",
       "if possible move left ; move right", "repeat {3 - 1} times { pick item ; move left }",
       "foreach point in [[1,4],[3,4]] { visit point }", "visit room1 or room2 containing item",
       "pick every item has color red and has shape square"});
}
