// The perceptron scorer: the scorer conformance kit through the kernel loader, the averaged
// update against hand-computed values, per-user models, state round trip.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "flipper/testing/scorer_conformance.hpp"
#include "kernel_loaded.hpp"

using namespace flipper;
using floatingtest::kernel_loaded;

namespace {

std::shared_ptr<sdk::Scorer> perceptron(std::vector<std::string> sets = {}) {
  return kernel_loaded<sdk::Scorer>("scorer", "perceptron", std::move(sets));
}

// A one-node derivation of a core rule `id` meaning `program`, with a parse-time score. Without
// tokens in the context its features are exactly: rule=<id>, fired, core.
sdk::DerivationPtr node(const std::string& id, const std::string& program, double score) {
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = id;
  rule->lhs = "$Action";
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule;
  d->sem = sdk::read_canonical(program);
  d->score = score;
  return d;
}

std::vector<sdk::Candidate> two(double score_a, double score_b) {
  std::vector<sdk::Candidate> cs(2);
  cs[0].derivations = {node("a", "{move left}", score_a)};
  cs[1].derivations = {node("b", "{move right}", score_b)};
  for (auto& c : cs) {
    c.program = c.derivations[0]->sem;
    c.score = c.derivations[0]->score;
  }
  return cs;
}

nlohmann::json weights(const sdk::Scorer& s, const std::string& user = "") {
  return nlohmann::json::parse(s.save_state()).at("models").at(user);
}

}  // namespace

TEST_CASE("perceptron passes the scorer conformance kit (kernel-loaded)") {
  auto parser = kernel_loaded<sdk::Parser>("parser", "chart");
  parser->set_grammar(parsetest::core_grammar());
  testing::check_scorer_conformance([] { return perceptron(); }, *parser,
                                    "visit room1 or room2 containing item is red or is blue");
}

TEST_CASE("averaged perceptron update, by hand") {
  auto s = perceptron();
  const sdk::ScoreContext ctx{nullptr, "alice"};
  // Accept b while a is predicted (1.0 > 0.5): Δ = φ(b) − φ(a) = +rule=b −rule=a (fired and core
  // cancel). At c = 1: w = Δ, u = 1·Δ; then c = 2, average = w − u/2 = Δ/2.
  auto cs = two(1.0, 0.5);
  s->learn(cs, 1, ctx);
  auto m = weights(*s);
  CHECK(m.at("c") == 2.0);
  CHECK(m.at("weights") == nlohmann::json::parse(R"({"rule=a":[-1.0,-1.0],"rule=b":[1.0,1.0]})"));
  CHECK(s->score_node(*cs[1].derivations[0], ctx) == 1.5);  // core bonus 1 + 0.5
  CHECK(s->score_node(*cs[0].derivations[0], ctx) == 0.5);  // 1 − 0.5
  // Accept b again, now predicted (scores as re-parsed): no update, but c = 3 and the average
  // moves towards w: 1 − 1/3.
  cs = two(0.5, 1.5);
  s->learn(cs, 1, ctx);
  CHECK(weights(*s).at("c") == 3.0);
  CHECK(s->score_node(*cs[1].derivations[0], ctx) == Approx(1.0 + 2.0 / 3.0));
  // Accept a while b is predicted: Δ = +rule=a −rule=b at c = 3: w_a = 0, u_a = −1 + 3 = 2,
  // w_b = 0, u_b = 1 − 3 = −2; c = 4: averages a = −0.5, b = +0.5 (the past still prefers b).
  s->learn(cs, 0, ctx);
  m = weights(*s);
  CHECK(m.at("c") == 4.0);
  CHECK(m.at("weights") == nlohmann::json::parse(R"({"rule=a":[0.0,2.0],"rule=b":[0.0,-2.0]})"));
  CHECK(s->score_node(*cs[0].derivations[0], ctx) == 0.5);
  CHECK(s->score_node(*cs[1].derivations[0], ctx) == 1.5);
  // A tie predicts the first candidate; rate scales the update.
  auto fast = perceptron({"scorer.params.rate=2"});
  cs = two(1.0, 1.0);
  fast->learn(cs, 1, ctx);
  CHECK(fast->score_node(*cs[1].derivations[0], ctx) == 2.0);  // 1 + (2 − 2/2)
  CHECK_THROWS_AS(fast->learn(cs, 2, ctx), sdk::Error);
}

TEST_CASE("perceptron: per-user models, state round trip") {
  auto s = perceptron({"scorer.params.per_user=true"});
  const sdk::ScoreContext alice{nullptr, "alice"}, bob{nullptr, "bob"};
  auto cs = two(1.0, 0.5);
  s->learn(cs, 1, alice);
  CHECK(s->score_node(*cs[1].derivations[0], alice) == 1.5);
  CHECK(s->score_node(*cs[1].derivations[0], bob) == 1.0);  // bob's model is untouched
  auto other = perceptron({"scorer.params.per_user=true"});
  other->load_state(s->save_state());
  CHECK(other->score_node(*cs[1].derivations[0], alice) == 1.5);
  CHECK(other->save_state() == s->save_state());
  CHECK_THROWS_AS(other->load_state(R"({"format":"flipper.loglinear/1","models":{}})"), sdk::Error);
  CHECK_THROWS_AS(
      other->load_state(R"({"format":"flipper.perceptron/1","models":{"":{"c":0,"weights":{}}}})"),
      sdk::Error);
  // A global model ignores the user.
  auto global = perceptron();
  global->learn(cs, 1, alice);
  CHECK(global->score_node(*cs[1].derivations[0], bob) == 1.5);
}
