// Per-user weights live in the scorer, keyed by user, under one switch (docs/naturalization.md §5
// "Learned state"): `scorer.params.per_user` (lexicon.weights = per_user writes it). The
// naturalizer keeps one weights key; a user's accepts move that user's ranking only, on every
// kernel over the store and after a restart; a store written the old way (a key per user) is
// folded into the one key without losing a weight.
#include <catch2/catch.hpp>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "naturalize_fixture.hpp"
#include "store_sql.hpp"

namespace {

using flipper::kernel::Json;
using flipper::kernel::Session;
using flipper::wiring::SessionHost;
namespace naturalization = flipper::naturalization;
using flipper::naturalizetest::sql;
using flipper::naturalizetest::sql_int;
using flipper::testsupport::scratch_path;

const std::string kAmbiguous = "pick item not is red and is green";

SessionHost host(const std::string& store, std::vector<std::string> sets) {
  sets.push_back("lexicon.path=" + store);
  return flipper::wiring::open_host(std::nullopt, sets);
}

// A session of `user` on `h`.
std::unique_ptr<Session> as(const SessionHost& h, const std::string& user) {
  auto s = h.open();
  s->activate();
  REQUIRE(s->handle({{"op", "user"}, {"name", user}})["ok"] == true);
  return s;
}

// The candidates of the ambiguous query as `s` ranks them (formulas and scores, printed to
// round-trip: equal texts are equal doubles).
std::string ranking(Session& s) {
  s.activate();
  const Json a = s.handle({{"op", "query"}, {"text", kAmbiguous}});
  REQUIRE(a.value("ok", false));
  REQUIRE(a["candidates"].size() >= 2);
  Json out = Json::array();
  for (const auto& c : a["candidates"]) out.push_back({c["formula"], c["score"]});
  return out.dump();
}

void accept_second(Session& s) {
  (void)ranking(s);
  REQUIRE(s.handle({{"op", "accept"}, {"rank", 1}})["ok"] == true);
}

// The oracle of ana's ranking after her accept: the same accept from the same start trains the
// one global partition of a global-weights kernel exactly as it trains ana's partition.
std::string global_oracle() {
  const SessionHost h = host(scratch_path("peruser-oracle") + ".sqlite", {});
  auto s = as(h, "ana");
  accept_second(*s);
  return ranking(*s);
}

}  // namespace

TEST_CASE(
    "per-user weights, one switch: a user's accepts move only that user's ranking, on "
    "every kernel and after a restart",
    "[naturalize][pool][per_user]") {
  const std::string oracle = global_oracle();
  // The switch either way; and with learn in a child process (plugins.isolation, docs/
  // plugins-untrusted.md §6: the child's values cross, WeightValues), budgets lifted as the
  // golden's isolated run does (a child's fork is charged to the request).
  const std::vector<std::vector<std::string>> switches = {
      {"lexicon.weights=per_user"},
      {"scorer.params.per_user=true"},
      {"lexicon.weights=per_user", "plugins.isolation=process", "lexicon.group_commit=false",
       "execution.cpu_budget_ms=86400000", "session.cpu_budget_ms=86400000"}};
  for (const auto& sw : switches) {
    INFO("switch: " << sw.front() << (sw.size() > 1 ? " + " + sw[1] : std::string()));
    const std::string store = scratch_path("peruser") + ".sqlite";
    std::string untrained;
    {
      const SessionHost k1 = host(store, sw);
      const SessionHost k2 = host(store, sw);
      auto ana = as(k1, "ana");
      auto bob = as(k2, "bob");
      untrained = ranking(*bob);
      REQUIRE(ranking(*ana) == untrained);
      REQUIRE(oracle != untrained);  // the accept changes the ranking at all
      accept_second(*ana);           // on kernel 1
      CHECK(ranking(*ana) == oracle);
      CHECK(ranking(*bob) == untrained);  // kernel 2, bob: untouched
      // ana on kernel 2, bob on kernel 1 (a server's pool moves sessions so).
      auto ana2 = as(k2, "ana");
      auto bob1 = as(k1, "bob");
      CHECK(ranking(*ana2) == oracle);
      CHECK(ranking(*bob1) == untrained);
      // One session switching user on one kernel: no state swapped, each sees their own.
      REQUIRE(ana->handle({{"op", "user"}, {"name", "bob"}})["ok"] == true);
      CHECK(ranking(*ana) == untrained);
      REQUIRE(ana->handle({{"op", "user"}, {"name", "ana"}})["ok"] == true);
      CHECK(ranking(*ana) == oracle);
      // bob learns on kernel 2 while ana's update stands: both kept, on both kernels.
      accept_second(*bob);
      const std::string bob_trained = ranking(*bob);
      CHECK(bob_trained == oracle);  // same accept from the same start, bob's own partition
      CHECK(ranking(*bob1) == bob_trained);
      CHECK(ranking(*ana2) == oracle);
    }
    // The store: one key, a partition per user; no per-user keys, no saved whole state.
    naturalization::LexiconStore stored(store);
    const auto weights = stored.weight_changes(naturalization::kWeightsKey);
    REQUIRE_FALSE(weights.empty());
    std::size_t ana_rows = 0, bob_rows = 0;
    for (const auto& w : weights) {
      CHECK((w.model == "ana" || w.model == "bob"));
      (w.model == "ana" ? ana_rows : bob_rows) += 1;
    }
    CHECK(ana_rows == bob_rows);
    CHECK(stored.legacy_user_weight_keys() == 0);
    CHECK_FALSE(stored.load_weights(naturalization::kWeightsKey));
    // After a restart.
    const SessionHost again = host(store, sw);
    CHECK(ranking(*as(again, "ana")) == oracle);
    CHECK(ranking(*as(again, "bob")) == oracle);
    CHECK(ranking(*as(again, "cy")) == untrained);
  }
}

TEST_CASE(
    "a store written the old way (a weights key per user) is folded into the scorer's "
    "partitions without losing a weight",
    "[naturalize][per_user][migration]") {
  const std::string oracle = global_oracle();
  const std::string untrained = [] {
    const SessionHost h = host(scratch_path("peruser-untrained") + ".sqlite", {});
    return ranking(*as(h, "x"));
  }();
  for (const std::string old_format : {"rows", "state"}) {
    INFO("old format: " << old_format);
    const std::string store = scratch_path("peruser-old") + ".sqlite";
    {  // ana learns (global weights: partition ""), then the store is rewritten as an older
       // build with lexicon.weights = per_user wrote it: her weights under key user:ana.
      const SessionHost h = host(store, {});
      accept_second(*as(h, "ana"));
    }
    REQUIRE(sql_int(store, "SELECT count(*) FROM scorer_weights WHERE key = 'global'") > 1);
    if (old_format == std::string("rows")) {
      sql(store, "UPDATE scorer_weights SET key = 'user:ana'");
    } else {  // a saved whole state (the loglinear format) holds all but one weight; a change
              // row holds the rest of that one: the old build loaded state + change
      sql(store,
          "INSERT INTO scorer_state(key, state, seq) SELECT 'user:ana', json_object('format', "
          "'flipper.loglinear/1', 'per_user', json('false'), 'models', json_object('', "
          "json_group_object(feature, json_array(weight, aux)))), 1 FROM scorer_weights");
      sql(store,
          "UPDATE scorer_weights SET key = 'user:ana', weight = 0, aux = 0 WHERE feature = "
          "(SELECT min(feature) FROM scorer_weights)");
      sql(store, "DELETE FROM scorer_weights WHERE key = 'global'");
      // An unreadable state of another user stays, with its rows, and is not served.
      sql(store, "INSERT INTO scorer_state(key, state, seq) VALUES ('user:zed', 'opaque', 1)");
      sql(store,
          "INSERT INTO scorer_weights(key, model, feature, weight, aux, seq) VALUES "
          "('user:zed', '', 'f', 1, 1, 1)");
    }
    REQUIRE(sql_int(store, "SELECT count(*) FROM scorer_weights WHERE key = 'global'") == 0);
    {
      const SessionHost h = host(store, {"lexicon.weights=per_user"});
      CHECK(ranking(*as(h, "ana")) == oracle);
      CHECK(ranking(*as(h, "bob")) == untrained);
    }
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_weights WHERE key = 'user:ana'") == 0);
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_state WHERE key = 'user:ana'") == 0);
    CHECK(sql_int(store,
                  "SELECT count(*) FROM scorer_weights WHERE key = 'global' AND model <> 'ana'") ==
          0);
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_weights WHERE key = 'user:zed'") ==
          (old_format == std::string("state") ? 1 : 0));
    // Folded once: a second start serves the same.
    const SessionHost again = host(store, {"lexicon.weights=per_user"});
    CHECK(ranking(*as(again, "ana")) == oracle);
  }
}

TEST_CASE("folding old per-user keys adds to the one key's sums (hand-computed)",
          "[naturalize][per_user][migration]") {
  const std::string store = scratch_path("peruser-fold") + ".sqlite";
  { naturalization::LexiconStore create(store); }
  sql(store,
      "INSERT INTO scorer_weights(key, model, feature, weight, aux, seq) VALUES "
      "('global', 'ana', 'f', 1.0, 2.0, 1), ('user:ana', '', 'f', 0.5, 0.25, 2), "
      "('user:ana', '', 'g', -3.0, 9.0, 2), ('user:bob', 'bob', 'f', 4.0, 16.0, 2)");
  sql(store,
      "INSERT INTO scorer_state(key, state, seq) VALUES ('user:bob', '{\"format\": \"x/1\", "
      "\"per_user\": false, \"models\": {\"\": {\"c\": 3, \"weights\": {\"f\": [0.125, 1]}}}}', "
      "2)");
  naturalization::LexiconStore s(store);
  REQUIRE(s.legacy_user_weight_keys() == 2);
  const auto kept = s.fold_user_weights(naturalization::kWeightsKey, [](const std::string&) {
    return std::optional<std::vector<naturalization::StoredWeightChange>>(
        {{"", "f", 0.125, 1.0}, {"", "#accepts", 2.0, 0.0}});
  });
  CHECK(kept.empty());
  CHECK(s.legacy_user_weight_keys() == 0);
  std::vector<std::string> rows;
  for (const auto& w : s.weight_changes(naturalization::kWeightsKey))
    rows.push_back(w.model + " " + w.feature + " " + std::to_string(w.weight) + " " +
                   std::to_string(w.aux));
  CHECK(rows == std::vector<std::string>{"ana f 1.500000 2.250000", "ana g -3.000000 9.000000",
                                         "bob #accepts 2.000000 0.000000",
                                         "bob f 4.125000 17.000000"});
}

TEST_CASE("an older store's saved linear-model state reads back as weights (hand-written)",
          "[naturalize][per_user][migration]") {
  using naturalization::linear_state_weights;
  const auto flat = linear_state_weights(
      R"({"format": "flipper.loglinear/1", "per_user": false,
          "models": {"": {"rule=a": [0.5, 0.25]}}})");
  REQUIRE(flat);
  REQUIRE(flat->size() == 1);
  CHECK((*flat)[0].model == "");
  CHECK((*flat)[0].feature == "rule=a");
  CHECK((*flat)[0].weight == 0.5);
  CHECK((*flat)[0].aux == 0.25);
  // The perceptron's layout: the counter c = 3 is the reserved weight #accepts = 2.
  const auto counted = linear_state_weights(
      R"({"format": "flipper.perceptron/1", "per_user": true,
          "models": {"ana": {"c": 3, "weights": {"rule=b": [-1.5, 4]}}}})");
  REQUIRE(counted);
  REQUIRE(counted->size() == 2);
  CHECK((*counted)[0].model == "ana");
  CHECK((*counted)[0].feature == "#accepts");
  CHECK((*counted)[0].weight == 2.0);
  CHECK((*counted)[1].feature == "rule=b");
  CHECK((*counted)[1].weight == -1.5);
  CHECK((*counted)[1].aux == 4.0);
  // Not such a state.
  CHECK_FALSE(linear_state_weights("opaque"));
  CHECK_FALSE(linear_state_weights(R"({"models": {}})"));
  CHECK_FALSE(
      linear_state_weights(R"({"format": "f", "models": {"": {"c": 0.5, "weights": {}}}})"));
  CHECK_FALSE(linear_state_weights(R"({"format": "f", "models": {"": {"a": 1}}})"));
}
