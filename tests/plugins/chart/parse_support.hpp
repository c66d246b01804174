#pragma once
// Shared helpers of the parser tests: the core grammar, the chart parser and loglinear scorer
// loaded as plugins, and a one-call parse of an utterance.
#include <memory>
#include <string>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/parser.hpp"
#include "plugin_fixture.hpp"

namespace flipper::parsetest {

inline std::shared_ptr<const sdk::Grammar> core_grammar() {
  static const auto g = std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/core.grammar",
      {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
      {"triangle", "circle", "square"}, {"up", "down", "left", "right"}));
  return g;
}

struct Stack {
  std::shared_ptr<sdk::Parser> parser = testsupport::load_plugin<sdk::Parser>("chart");
  std::shared_ptr<sdk::Scorer> scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");
  Stack() { parser->set_grammar(core_grammar()); }

  sdk::ParseResult parse(const std::string& utterance, const std::string& user = "u") const {
    sdk::ParseRequest req;
    req.tokens = sdk::tokenize(utterance);
    req.scorer = scorer.get();
    req.context.user = user;
    return parser->parse(req);
  }
};

/// The parser and scorer are loaded once per test binary (loading is the slow part).
inline Stack& shared_stack() {
  static Stack s;
  return s;
}

}  // namespace flipper::parsetest
