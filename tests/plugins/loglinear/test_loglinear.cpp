// The loglinear scorer: conformance kit, features of §3, per-user weights, state round trip.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <tuple>

#include "flipper/testing/scorer_conformance.hpp"
#include "plugins/chart/parse_support.hpp"

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
  sdk::Derivation d;
  d.rule = std::make_shared<sdk::Rule>(std::move(rule));
  d.start = 0;
  d.end = 2;
  d.core_only = false;
  // Use counts come from the kernel's counters in the context, not from the rule.
  f.clear();
  st.scorer->features(d, ctx, f);
  CHECK(has("used_by_others=no"));
  CHECK_FALSE(has("uses_by_others"));
  struct Counters : sdk::UsageCounters {
    sdk::RuleUses uses(const std::string& id) const override {
      return id == "r9" ? sdk::RuleUses{0, 3} : sdk::RuleUses{};
    }
  } counters;
  ctx.usage = &counters;
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

TEST_CASE("per-user weights learn separately, bad accept index is rejected") {
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

namespace {

/// A one-node derivation of a core rule `id` over no tokens (features: rule=id, fired, core).
sdk::Candidate one_node_candidate(const std::string& id, double score) {
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = id;
  rule->lhs = "$Action";
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule;
  d->score = score;
  sdk::Candidate c;
  c.derivations.push_back(d);
  c.score = score;
  return c;
}

/// (weight, AdaGrad sum) of a feature in the scorer's saved state.
std::pair<double, double> weight_of(const sdk::Scorer& scorer, const std::string& feature) {
  const auto j = nlohmann::json::parse(scorer.save_state());
  const auto& w = j.at("models").at("").at(feature);
  return {w.at(0).get<double>(), w.at(1).get<double>()};
}

}  // namespace

TEST_CASE("the AdaGrad + L1 update is pinned to hand-computed values (naturalization §3)",
          "[scorer][defects]") {
  auto scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");
  const std::vector<std::string> tokens;
  const sdk::ScoreContext ctx{&tokens, "ana"};
  // Accept A between two tied candidates: p_model = 1/2 each, so g = +1/2 for rule=a,
  // -1/2 for rule=b, 0 for the shared `fired` and `core` (not updated at all).
  // G = 1/4; rate = 0.1 / sqrt(1/4 + 1); w = rate * 1/2, then L1 moves it rate * 1e-4 toward 0:
  // w_a = 0.1 / sqrt(1.25) * (0.5 - 1e-4) = 0.0447124152780858, w_b = -w_a.
  scorer->learn({one_node_candidate("a", 0), one_node_candidate("b", 0)}, 0, ctx);
  auto [wa, ga] = weight_of(*scorer, "rule=a");
  auto [wb, gb] = weight_of(*scorer, "rule=b");
  CHECK(ga == 0.25);
  CHECK(gb == 0.25);
  CHECK(wa == Approx(0.0447124152780858).epsilon(1e-12));
  CHECK(wb == Approx(-0.0447124152780858).epsilon(1e-12));
  const auto saved = nlohmann::json::parse(scorer->save_state());
  CHECK_FALSE(saved.at("models").at("").contains("fired"));
  CHECK_FALSE(saved.at("models").at("").contains("core"));

  // A second accept of A, scored with those weights: p_A = e^w_a / (e^w_a + e^-w_a),
  // g = 1 - p_A = 0.47765867863418177, G = 0.25 + g^2 = 0.47815781327455253,
  // w_a += 0.1 / sqrt(G + 1) * (g - 1e-4) = 0.08399195048958408.
  scorer->learn({one_node_candidate("a", wa), one_node_candidate("b", wb)}, 0, ctx);
  std::tie(wa, ga) = weight_of(*scorer, "rule=a");
  CHECK(ga == Approx(0.47815781327455253).epsilon(1e-12));
  CHECK(wa == Approx(0.08399195048958408).epsilon(1e-12));
}
