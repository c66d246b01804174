// The loglinear scorer: conformance kit, features of §3, per-user weights, state round trip.
#include <catch2/catch.hpp>

#include "../parser/parse_support.hpp"
#include "flipper/testing/scorer_conformance.hpp"

using namespace flipper;

TEST_CASE("loglinear passes the scorer conformance kit") {
  auto parser = testsupport::load_plugin<sdk::Parser>("chart");
  parser->set_grammar(parsetest::core_grammar());
  testing::check_scorer_conformance(
      [] { return testsupport::load_plugin<sdk::Scorer>("loglinear"); }, *parser,
      "visit room1 or room2 containing item is red or is blue");
}

TEST_CASE("features of a node and the initial score") {
  auto& st = parsetest::shared_stack();
  auto r = st.parse("visit world");
  REQUIRE(r.candidates.size() == 1);
  const auto& root = *r.candidates[0].derivations[0];
  CHECK(r.candidates[0].score == 5.0);
  const std::vector<std::string> tokens = {"visit", "world"};
  sdk::ScoreContext ctx{&tokens, "alice"};
  sdk::FeatureVector f;
  st.scorer->features(*root.kids[0]->kids[0], ctx, f);  // $Action -> visit $Areas
  auto has = [&](const std::string& name) {
    for (const auto& [n, v] : f)
      if (n == name) return true;
    return false;
  };
  CHECK(has("fired"));
  CHECK(has("core"));
  CHECK(has("cat_len=$Action,2"));
  CHECK(has("cat_span=$Action,visit...world"));
  CHECK(has("ctx1=^,$Action,$"));
  CHECK(has("ctx2=^ ^,$Action,$ $"));
  CHECK_FALSE(has("induced"));
  // Induced rule features.
  sdk::Rule rule;
  rule.id = "r9";
  rule.lhs = "$Action";
  rule.induced = true;
  rule.how = sdk::RuleOrigin::alignment;
  rule.author = "bob";
  rule.usage->by_others = 3;
  sdk::Derivation d;
  d.rule = std::make_shared<sdk::Rule>(std::move(rule));
  d.start = 0;
  d.end = 2;
  d.core_only = false;
  f.clear();
  st.scorer->features(d, ctx, f);
  CHECK(has("induced"));
  CHECK(has("used_by_others=yes"));
  CHECK(has("used_by_author=no"));
  CHECK(has("alignment=yes"));
  CHECK(has("author=bob"));
  CHECK(has("author_user=bob,alice"));
  CHECK(has("self=no"));
  for (const auto& [n, v] : f)
    if (n == "uses_by_others") CHECK(v == 3.0);
  CHECK(st.scorer->score_node(d, ctx) == 0.0);
}

TEST_CASE("per-user weights learn separately; bad accept index is rejected") {
  auto parser = testsupport::load_plugin<sdk::Parser>("chart");
  parser->set_grammar(parsetest::core_grammar());
  auto scorer =
      testsupport::load_plugin<sdk::Scorer>("loglinear", sdk::Params({{"per_user", true}}));
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize("visit room1 or room2 containing item");
  req.scorer = scorer.get();
  req.context.user = "alice";
  auto r = parser->parse(req);
  REQUIRE(r.candidates.size() == 2);
  sdk::ScoreContext ctx{&req.tokens, "alice"};
  scorer->learn(r.candidates, 1, ctx);
  auto mine = parser->parse(req);
  req.context.user = "bob";
  auto theirs = parser->parse(req);
  CHECK(mine.candidates[0].score > mine.candidates[1].score);
  CHECK(theirs.candidates[0].score == theirs.candidates[1].score);
  CHECK_THROWS_AS(scorer->learn(r.candidates, 7, ctx), sdk::Error);
  // Round trip keeps per-user weights.
  auto other =
      testsupport::load_plugin<sdk::Scorer>("loglinear", sdk::Params({{"per_user", true}}));
  other->load_state(scorer->save_state());
  req.scorer = other.get();
  req.context.user = "alice";
  auto again = parser->parse(req);
  CHECK(again.candidates[0].score == mine.candidates[0].score);
}
