// example_parser's own tests, beside the conformance kits: the plugin created as the kernel
// creates it (testing::load_plugin validates its parameters), with the core grammar the kit uses
// (FLIPPER_CONFORMANCE_GRAMMAR, installed with the SDK) and the core bonus as the score.
#include <catch2/catch.hpp>
#include <flipper/sdk/canonical.hpp>
#include <flipper/sdk/parser.hpp>
#include <flipper/testing/core_scorer.hpp>
#include <flipper/testing/plugin_factory.hpp>

namespace {

namespace sdk = flipper::sdk;

std::vector<std::string> readings(const sdk::Parser& parser, const std::string& text) {
  const flipper::testing::CoreScorer scorer;
  sdk::ParseRequest request;
  request.tokens = sdk::tokenize(text);
  request.scorer = &scorer;
  std::vector<std::string> out;
  for (const auto& c : parser.parse(request).candidates) out.push_back(sdk::render(c.program));
  return out;
}

}  // namespace

TEST_CASE("example_parser: synonyms are read as the words they stand for") {
  using flipper::testing::load_plugin;
  const auto grammar = std::make_shared<const sdk::Grammar>(
      sdk::load_grammar_file(FLIPPER_CONFORMANCE_GRAMMAR, {"red"}, {"circle"}, {"up", "left"}));
  const auto parser = load_plugin<sdk::Parser>("example_parser");
  parser->set_grammar(grammar);
  CHECK(readings(*parser, "go room1") == std::vector<std::string>{"{visit room1}"});
  CHECK(readings(*parser, "visit room1") == std::vector<std::string>{"{visit room1}"});
  const auto plain =
      load_plugin<sdk::Parser>("example_parser", {{"synonyms", std::vector<std::string>{}}});
  plain->set_grammar(grammar);
  CHECK(readings(*plain, "go room1").empty());
  CHECK_THROWS_AS(
      load_plugin<sdk::Parser>("example_parser", {{"synonyms", std::vector<std::string>{"go"}}}),
      flipper::sdk::Error);
}
