// Per-user weights live in the scorer, keyed by user, under one switch (docs/naturalization.md §5
// "Learned state"): `scorer.params.per_user` (lexicon.weights = per_user writes it). The
// naturalizer keeps one weights key; a user's accepts move that user's ranking only, on every
// kernel over the store and after a restart; a store written the old way (a key per user) is
// folded into the one key without losing a weight, its saved states read by the scorer whose
// format they are (sdk::StateWeights), its answer checked; a scorer that cannot read them keeps
// them unserved, with a warning.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "flipper/kernel/runtime.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "naturalize_fixture.hpp"
#include "product_schema.hpp"
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
  const auto kept = s.fold_user_weights(
      naturalization::kWeightsKey, [](const std::string& key, const std::string&) {
        CHECK(key == "user:bob");
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

namespace {

namespace kernel = flipper::kernel;
namespace sdk = flipper::sdk;

// The config's scorer behind a wrapper that forwards the Scorer calls and has no other
// capability: no sdk::StateWeights (nor IncrementalScorer: it saves whole states).
class Forwarding : public sdk::Scorer {
 public:
  explicit Forwarding(std::shared_ptr<sdk::Scorer> inner) : inner_(std::move(inner)) {}

 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext& ctx) const override {
    return inner_->score_node(node, ctx);
  }
  void do_features(const sdk::Derivation& node, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out) const override {
    inner_->features(node, ctx, out);
  }
  void do_learn(const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                const sdk::ScoreContext& ctx) override {
    inner_->learn(candidates, accepted, ctx);
  }
  std::string do_save_state() const override { return inner_->save_state(); }
  void do_load_state(std::string_view state) override { inner_->load_state(state); }

  std::shared_ptr<sdk::Scorer> inner_;
};

using Answer = std::function<std::optional<std::vector<sdk::WeightChange>>(std::string_view)>;

// The same with sdk::StateWeights, answering as `answer` says.
class Answering : public Forwarding, public sdk::StateWeights {
 public:
  Answering(std::shared_ptr<sdk::Scorer> inner, Answer answer)
      : Forwarding(std::move(inner)), answer_(std::move(answer)) {}

 protected:
  std::optional<std::vector<sdk::WeightChange>> do_state_weights(
      std::string_view saved_state) const override {
    return answer_(saved_state);
  }

 private:
  Answer answer_;
};

// A store of an older build: ana's weights as a whole state saved by loglinear (the default
// scorer), under user:ana.
const std::string kAnaState =
    R"({"format":"flipper.loglinear/1","per_user":false,"models":{"":{"rule=a":[0.5,0.25]}}})";

std::string old_store() {
  const std::string store = scratch_path("peruser-reader") + ".sqlite";
  { naturalization::LexiconStore create(store); }
  sql(store,
      "INSERT INTO scorer_state(key, state, seq) VALUES ('user:ana', '" + kAnaState + "', 1)");
  return store;
}

// Starts a naturalizer over `store` whose scorer is made by `wrap` from the config's; its
// warnings.
std::vector<std::string> start(
    const std::string& store,
    const std::function<std::shared_ptr<sdk::Scorer>(std::shared_ptr<sdk::Scorer>)>& wrap) {
  std::shared_ptr<kernel::Runtime> rt =
      kernel::make_runtime(kernel::Config::load(std::nullopt, {"lexicon.path=" + store}));
  rt->scorer = kernel::PluginRef<sdk::Scorer>(wrap(rt->scorer.shared()));
  auto options = naturalization::NaturalizeOptions::from_config(rt->config);
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  naturalization::Naturalizer nat(rt, options);
  return warnings;
}

// The one warning, checked to name the kept key.
std::string kept_warning(const std::vector<std::string>& warnings) {
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("the saved scorer state under 'user:ana'") &&
                              Catch::Contains("it is kept, not served"));
  return warnings[0];
}

}  // namespace

TEST_CASE("an older store's saved state is read by the scorer, checked, or kept with a warning",
          "[naturalize][per_user][migration]") {
  const auto reads = [](std::shared_ptr<sdk::Scorer> inner) {
    return [inner](std::string_view s) {
      return dynamic_cast<const sdk::StateWeights&>(*inner).state_weights(s);
    };
  };
  SECTION("the scorer's own reading (through the wrapper): folded") {
    const std::string store = old_store();
    CHECK(start(store, [&](auto inner) {
            return std::make_shared<Answering>(inner, reads(inner));
          }).empty());
    naturalization::LexiconStore s(store);
    CHECK(s.legacy_user_weight_keys() == 0);
    const auto w = s.weight_changes(naturalization::kWeightsKey);
    REQUIRE(w.size() == 1);
    CHECK(w[0].model == "ana");
    CHECK(w[0].feature == "rule=a");
    CHECK(w[0].weight == 0.5);
    CHECK(w[0].aux == 0.25);
  }
  SECTION("a scorer without sdk::StateWeights: kept") {
    const std::string store = old_store();
    const auto w =
        kept_warning(start(store, [](auto inner) { return std::make_shared<Forwarding>(inner); }));
    CHECK_THAT(w, Catch::Contains("plugin 'in-process' (scorer) does not read its saved states "
                                  "as weights"));
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_state WHERE key = 'user:ana'") == 1);
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_weights") == 0);
  }
  SECTION("a weight or aux that is not finite: refused, kept") {
    for (const double bad :
         {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      for (const bool in_aux : {false, true}) {
        INFO("bad " << bad << (in_aux ? " in aux" : " in the weight"));
        const std::string store = old_store();
        const auto w = kept_warning(start(store, [&](auto inner) {
          return std::make_shared<Answering>(inner, [&, read = reads(inner)](std::string_view s) {
            auto r = read(s);
            (in_aux ? r->back().aux : r->back().weight) = bad;
            return r;
          });
        }));
        CHECK_THAT(w, Catch::Contains("[invalid_weights] plugin 'in-process' (scorer): "
                                      "state_weights: the weight 'rule=a' of partition ''") &&
                          Catch::Contains("not a finite number"));
        CHECK(sql_int(store, "SELECT count(*) FROM scorer_state WHERE key = 'user:ana'") == 1);
        CHECK(sql_int(store, "SELECT count(*) FROM scorer_weights") == 0);
      }
    }
  }
  SECTION("more weights than the state has bytes: refused, kept") {
    const std::string store = old_store();
    const auto w = kept_warning(start(store, [](auto inner) {
      return std::make_shared<Answering>(inner, [](std::string_view s) {
        return std::optional<std::vector<sdk::WeightChange>>(
            std::vector<sdk::WeightChange>(s.size() + 1, sdk::WeightChange{"", "f", 1, 0}));
      });
    }));
    CHECK_THAT(w, Catch::Contains("[invalid_weights]") &&
                      Catch::Contains(std::to_string(kAnaState.size() + 1) +
                                      " weights read from a saved state of " +
                                      std::to_string(kAnaState.size()) + " bytes"));
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_weights") == 0);
  }
  SECTION("a reading that throws, or reads no state: kept") {
    const std::string store = old_store();
    const auto w = kept_warning(start(store, [](auto inner) {
      return std::make_shared<Answering>(
          inner, [](std::string_view) -> std::optional<std::vector<sdk::WeightChange>> {
            throw std::runtime_error("cannot read");
          });
    }));
    CHECK_THAT(w, Catch::Contains("[plugin_error] plugin 'in-process' (scorer): state_weights: "
                                  "cannot read"));
    const auto none = kept_warning(start(store, [](auto inner) {
      return std::make_shared<Answering>(inner, [](std::string_view) { return std::nullopt; });
    }));
    CHECK_THAT(none, Catch::Contains("does not read it as a state it saved"));
    CHECK(sql_int(store, "SELECT count(*) FROM scorer_state WHERE key = 'user:ana'") == 1);
  }
}
