// example_scorer's own tests, beside the conformance kits: the plugin created as the kernel
// creates it (testing::load_plugin validates its parameters), on two readings of one node each
// whose features are exactly rule=<id>, fired and core (no tokens in the context).
#include <catch2/catch.hpp>
#include <flipper/sdk/canonical.hpp>
#include <flipper/sdk/scorer.hpp>
#include <flipper/testing/plugin_factory.hpp>

namespace {

namespace sdk = flipper::sdk;

sdk::Candidate reading(const std::string& rule_id, const std::string& program) {
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = rule_id;
  rule->lhs = "$ROOT";
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule;
  d->sem = sdk::read_canonical(program);
  sdk::Candidate c;
  c.program = d->sem;
  c.derivations = {d};
  return c;
}

}  // namespace

TEST_CASE("example_scorer: an accept moves rate towards the accepted reading") {
  const std::vector<sdk::Candidate> readings = {reading("a", "{move up}"),
                                                reading("b", "{move left}")};
  const sdk::ScoreContext ctx{nullptr, "ana", nullptr};
  const auto scorer = flipper::testing::load_plugin<sdk::Scorer>("example_scorer", {{"rate", 0.5}});
  const auto& a = *readings[0].derivations[0];
  const auto& b = *readings[1].derivations[0];
  CHECK(scorer->score_node(a, ctx) == 1.0);  // the core bonus, no weights yet
  scorer->learn(readings, 1, ctx);
  // rule=b +0.5, rule=a -0.5; fired and core cancel out.
  CHECK(scorer->score_node(b, ctx) == 1.5);
  CHECK(scorer->score_node(a, ctx) == 0.5);
  // The saved state holds exactly these two weights, and another instance reads it back.
  const auto other = flipper::testing::load_plugin<sdk::Scorer>("example_scorer");
  other->load_state(scorer->save_state());
  CHECK(other->score_node(b, ctx) == 1.5);
  CHECK(other->save_state() == scorer->save_state());
}
