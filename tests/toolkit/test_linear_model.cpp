// The toolkit's linear model (flipper/toolkit/linear_model.hpp): pending changes, their undo and
// commit, stored changes added in (sdk::IncrementalScorer, docs/naturalization.md §5), the accept
// counter, per-user partitions and the saved state in both layouts.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/linear_model.hpp"

using namespace flipper;
using toolkit::LinearModel;

namespace {

const toolkit::LinearStateFormat kFlat{"flat", "flat/1", ""};
const toolkit::LinearStateFormat kCounted{"counted", "counted/1", "c"};

// One node of rule `id` (not core-only: no bonus); its features are rule=<id>, fired, core.
sdk::DerivationPtr node(const std::string& id) {
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = id;
  rule->lhs = "$Action";
  auto d = std::make_shared<sdk::Derivation>();
  d->rule = rule;
  d->core_only = false;
  return d;
}

// w·φ with the weights as they are.
double score(const LinearModel& m, const sdk::Derivation& d, const sdk::ScoreContext& ctx) {
  return m.score_node(d, ctx, [](const toolkit::LinearWeight& w) { return w.w; });
}

// Adds `amount` to the weight (and 2·amount to aux) of every feature of `d`.
void update(LinearModel& m, const sdk::Derivation& d, const sdk::ScoreContext& ctx, double amount) {
  toolkit::features::SparseVector v;
  m.add_tree_features(d, ctx, amount, v);
  for (const auto& [key, x] : v) {
    auto& w = m.change(ctx, key);
    w.w += x;
    w.aux += 2 * x;
  }
}

}  // namespace

TEST_CASE("linear model: pending changes, discard restores exactly, commit keeps") {
  LinearModel m(false);
  const sdk::ScoreContext ctx{nullptr, "ana", nullptr};
  const auto a = node("a");
  update(m, *a, ctx, 0.25);
  CHECK(score(m, *a, ctx) == 0.75);  // three features at 0.25
  auto pending = m.pending_changes();
  REQUIRE(pending.size() == 3);
  for (const auto& c : pending) {
    CHECK(c.model.empty());
    CHECK(c.weight == 0.25);
    CHECK(c.aux == 0.5);
  }
  m.discard_changes();
  CHECK(score(m, *a, ctx) == 0.0);
  CHECK(m.pending_changes().empty());
  update(m, *a, ctx, 0.25);
  m.commit_changes();
  CHECK(m.pending_changes().empty());
  update(m, *a, ctx, 0.5);  // the change since the commit only
  pending = m.pending_changes();
  REQUIRE(pending.size() == 3);
  CHECK(pending[0].weight == 0.5);
  m.discard_changes();
  CHECK(score(m, *a, ctx) == 0.75);
}

TEST_CASE("linear model: two learners' changes add up in a third model") {
  const sdk::ScoreContext ctx{nullptr, "ana", nullptr};
  const auto a = node("a"), b = node("b");
  LinearModel one(false), two(false), both(false);
  update(one, *a, ctx, 1.0);
  update(two, *a, ctx, 2.0);
  update(two, *b, ctx, 1.0);
  both.apply_changes(one.pending_changes());
  both.apply_changes(two.pending_changes());
  CHECK(score(both, *a, ctx) == 3 * (1.0 + 2.0) + 1.0 + 1.0);  // rule=a 3; fired, core 4 each
  CHECK(score(both, *b, ctx) == 1.0 + 4 + 4);
  // The saved state names every weight: a fresh model loaded from it scores the same.
  LinearModel copy(false);
  copy.load_state(both.save_state(kFlat), kFlat);
  CHECK(score(copy, *a, ctx) == score(both, *a, ctx));
  CHECK(copy.save_state(kFlat) == both.save_state(kFlat));
}

TEST_CASE("linear model: the accept counter is a pending change and the counted layout's c") {
  LinearModel m(true);
  const sdk::ScoreContext ana{nullptr, "ana", nullptr}, bob{nullptr, "bob", nullptr};
  update(m, *node("a"), ana, 1.0);
  m.count_accept(ana);
  m.count_accept(ana);
  CHECK(LinearModel::accepts(*m.find(ana)) == 2.0);
  CHECK(m.find(bob) == nullptr);  // per user: bob's partition never learnt
  bool counted = false;
  for (const auto& c : m.pending_changes())
    if (c.feature == toolkit::kAcceptsFeature) {
      CHECK(c.model == "ana");
      CHECK(c.weight == 2.0);
      counted = true;
    }
  CHECK(counted);
  const auto state = nlohmann::json::parse(m.save_state(kCounted));
  CHECK(state.at("format") == "counted/1");
  CHECK(state.at("models").at("ana").at("c") == 3.0);
  CHECK(state.at("models").at("ana").at("weights").size() == 3);  // without #accepts
  LinearModel back(true);
  back.load_state(m.save_state(kCounted), kCounted);
  CHECK(LinearModel::accepts(*back.find(ana)) == 2.0);
  CHECK(back.save_state(kCounted) == m.save_state(kCounted));
  // Stored changes of the counter add up like any weight.
  back.apply_changes({{"ana", std::string(toolkit::kAcceptsFeature), 3.0, 0.0}});
  CHECK(LinearModel::accepts(*back.find(ana)) == 5.0);
}

TEST_CASE("linear model: an unreadable state is refused naming the plugin, nothing changes") {
  LinearModel m(false);
  const sdk::ScoreContext ctx{nullptr, "ana", nullptr};
  update(m, *node("a"), ctx, 1.0);
  const std::string before = m.save_state(kCounted);
  auto refused = [&](const std::string& state) -> std::string {
    try {
      m.load_state(state, kCounted);
    } catch (const sdk::Error& e) {
      CHECK(e.code() == sdk::codes::kBadConfig);
      return e.what();
    }
    return "(accepted)";
  };
  CHECK(refused(R"({"format":"flat/1","models":{}})") ==
        "counted: unknown state format (want counted/1)");
  CHECK(refused(R"({"format":"counted/1","models":{"":{"c":0.5,"weights":{}}}})") ==
        "counted: bad counter c in the state");
  CHECK_THAT(refused("not json {"), Catch::StartsWith("counted: unreadable state: "));
  CHECK(m.save_state(kCounted) == before);
}

TEST_CASE(
    "linear model: a saved state reads back as weights, as load_state loads it (hand-written)") {
  const auto flat = LinearModel::state_weights(
      R"({"format": "flat/1", "per_user": false, "models": {"": {"rule=a": [0.5, 0.25]}}})", kFlat);
  REQUIRE(flat);
  REQUIRE(flat->size() == 1);
  CHECK((*flat)[0].model == "");
  CHECK((*flat)[0].feature == "rule=a");
  CHECK((*flat)[0].weight == 0.5);
  CHECK((*flat)[0].aux == 0.25);
  // The counted layout: a partition's counter c = 3 is the reserved weight #accepts = 2, before
  // its weights; c = 1 is no accept.
  const auto counted = LinearModel::state_weights(
      R"({"format": "counted/1", "per_user": true,
          "models": {"ana": {"c": 3, "weights": {"rule=b": [-1.5, 4]}},
                     "bob": {"c": 1, "weights": {"rule=c": [0.125, 1]}}}})",
      kCounted);
  REQUIRE(counted);
  REQUIRE(counted->size() == 3);
  CHECK((*counted)[0].model == "ana");
  CHECK((*counted)[0].feature == "#accepts");
  CHECK((*counted)[0].weight == 2.0);
  CHECK((*counted)[0].aux == 0.0);
  CHECK((*counted)[1].model == "ana");
  CHECK((*counted)[1].feature == "rule=b");
  CHECK((*counted)[1].weight == -1.5);
  CHECK((*counted)[1].aux == 4.0);
  CHECK((*counted)[2].model == "bob");
  CHECK((*counted)[2].feature == "rule=c");
  CHECK((*counted)[2].weight == 0.125);
  CHECK((*counted)[2].aux == 1.0);
  // Not a state of this format: nullopt exactly where load_state refuses.
  for (const std::string text :
       {"opaque", R"({"models": {}})", R"({"format": "flat/1", "models": {}})",
        R"({"format": "counted/1", "models": {"": {"c": 0.5, "weights": {}}}})",
        R"({"format": "counted/1", "models": {"": {"c": -3, "weights": {}}}})",
        R"({"format": "counted/1", "models": {"": {"weights": {}}}})",
        R"({"format": "counted/1", "models": {"": {"c": 2, "weights": {"a": 1}}}})"}) {
    INFO(text);
    CHECK_FALSE(LinearModel::state_weights(text, kCounted));
    LinearModel m(false);
    CHECK_THROWS_AS(m.load_state(text, kCounted), sdk::Error);
  }
  CHECK_FALSE(
      LinearModel::state_weights(R"({"format": "flat/1", "models": {"": {"a": 1}}})", kFlat));
  // What a model saves reads back as its weights: added to an empty model, the same state.
  LinearModel m(true);
  const sdk::ScoreContext ana{nullptr, "ana", nullptr}, bob{nullptr, "bob", nullptr};
  update(m, *node("a"), ana, 0.75);
  update(m, *node("b"), bob, -0.5);
  m.count_accept(ana);
  m.count_accept(ana);
  m.count_accept(bob);
  m.commit_changes();
  for (const auto* format : {&kFlat, &kCounted}) {
    const std::string state = m.save_state(*format);
    const auto weights = LinearModel::state_weights(state, *format);
    REQUIRE(weights);
    CHECK(weights->size() == 8);  // 3 features and #accepts in each partition
    LinearModel back(true);
    back.apply_changes(*weights);
    CHECK(back.save_state(*format) == state);
    CHECK(LinearModel::accepts(*back.find(ana)) == 2.0);
  }
}
