// define / rules / delete_rule through the session protocol: sharing modes, authorship,
// deletion history, generalization, persistence across restarts, preload.
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "naturalize_fixture.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

TEST_CASE("define answers the rules it added and the next query uses them", "[naturalize]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  user(*s, "ana");
  CHECK(status(*s, "pick 3 items") == "unparsable");
  const Json a = define(*s, "pick 3 items", {"repeat 3 times pick item"});
  REQUIRE(a["ok"] == true);
  REQUIRE(a["rules"].size() >= 1);
  const Json& r = a["rules"][0];
  for (const char* f : {"id", "lhs", "rhs", "semantics", "author", "how"}) CHECK(r.contains(f));
  CHECK(r["author"] == "ana");
  CHECK(r["lhs"] == "$Action");
  CHECK(a.contains("generalized"));
  CHECK(status(*s, "pick 5 items") == "induced");
  const Json q = s->handle({{"op", "query"}, {"text", "pick 5 items"}});
  CHECK(q["candidates"][0]["formula"] == "{repeat 5 times {pick item }}");
}

TEST_CASE("definition errors have their codes", "[naturalize]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  CHECK(error_code(define(*s, " ", {"move left"})) == "empty_head");
  CHECK(error_code(define(*s, "move left", {"move right"})) == "head_is_core");
  const Json bad = define(*s, "do it", {"move left", "fly away"});
  CHECK(error_code(bad) == "body_unparsable");
  CHECK_THAT(bad["error"]["message"].get<std::string>(), Catch::Contains("line 2"));
  CHECK(error_code(s->handle({{"op", "define"}, {"head", "x"}})) == "missing_field");
  CHECK(s->handle({{"op", "rules"}})["rules"].empty());  // nothing was added by the failures
}

TEST_CASE("sharing modes decide whose rules a user parses with", "[naturalize]") {
  for (const std::string mode : {"shared", "private", "core"}) {
    DYNAMIC_SECTION("lexicon.sharing=" << mode) {
      auto s = open(scratch_path("lex") + ".sqlite", {"lexicon.sharing=" + mode});
      user(*s, "ana");
      REQUIRE(define(*s, "go west", {"move left"})["ok"] == true);
      const std::string own = status(*s, "go west");
      user(*s, "bob");
      const std::string other = status(*s, "go west");
      const auto listed = s->handle({{"op", "rules"}})["rules"].size();
      if (mode == "shared") {
        CHECK(own == "induced");
        CHECK(other == "induced");
        CHECK(listed >= 1);
      } else if (mode == "private") {
        CHECK(own == "induced");
        CHECK(other == "unparsable");
        CHECK(listed == 0);
        user(*s, "ana");
        CHECK(s->handle({{"op", "rules"}})["rules"].size() >= 1);
      } else {
        CHECK(own == "unparsable");
        CHECK(other == "unparsable");
        CHECK(listed == 0);
      }
      // head_is_core applies in every mode
      CHECK(error_code(define(*s, "move up", {"move down"})) == "head_is_core");
    }
  }
}

TEST_CASE("only the author deletes a rule, the store keeps the history", "[naturalize]") {
  const std::string store = scratch_path("lex") + ".sqlite";
  std::string id;
  {
    auto s = open(store);
    user(*s, "ana");
    const Json a = define(*s, "go west", {"move left"});
    REQUIRE(a["rules"].size() == 1);
    id = a["rules"][0]["id"];
    user(*s, "bob");
    CHECK(error_code(s->handle({{"op", "delete_rule"}, {"rule", id}})) == "forbidden");
    CHECK(error_code(s->handle({{"op", "delete_rule"}, {"rule", "r999"}})) == "not_found");
    CHECK(status(*s, "go west") == "induced");
    user(*s, "ana");
    const Json d = s->handle({{"op", "delete_rule"}, {"rule", id}});
    CHECK(d["deleted"] == id);
    CHECK(status(*s, "go west") == "unparsable");
    CHECK(s->handle({{"op", "rules"}})["rules"].empty());
    CHECK(error_code(s->handle({{"op", "delete_rule"}, {"rule", id}})) == "not_found");
  }
  naturalization::LexiconStore reopened(store);
  CHECK(reopened.rules().empty());
  REQUIRE(reopened.rules(true).size() == 1);
  CHECK(reopened.rules(true)[0].deleted);
  CHECK(reopened.definitions().size() == 1);
}

TEST_CASE("rules lists provenance and uses, filtered by author", "[naturalize]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  user(*s, "ana");
  define(*s, "go west", {"move left"});
  user(*s, "bob");
  define(*s, "go east", {"move right"});
  REQUIRE(status(*s, "go west") == "induced");
  REQUIRE(s->handle({{"op", "accept"}, {"rank", 0}})["ok"] == true);
  const Json all = s->handle({{"op", "rules"}});
  REQUIRE(all["rules"].size() == 2);
  const Json ana = s->handle({{"op", "rules"}, {"author", "ana"}});
  REQUIRE(ana["rules"].size() == 1);
  const Json& r = ana["rules"][0];
  CHECK(r["head"] == "go west");
  CHECK(r["body"] == Json::array({"move left"}));
  CHECK(r["how"] == "simple");
  CHECK(r["uses_by_others"] == 1);  // bob accepted ana's rule
  CHECK(r["uses_by_author"] == 0);
  CHECK(r["uses"] == 1);
}

TEST_CASE("rules, counters and weights survive a restart", "[naturalize]") {
  const std::string store = scratch_path("lex") + ".sqlite";
  std::string weights;
  {
    auto s = open(store);
    user(*s, "ana");
    define(*s, "pick 3 items", {"repeat 3 times pick item"});
    REQUIRE(status(*s, "pick 2 items") == "induced");
    REQUIRE(s->handle({{"op", "accept"}, {"rank", 0}})["ok"] == true);
    weights = s->runtime().scorer.borrow()->save_state();
  }
  auto s = open(store);
  CHECK(s->runtime().scorer.borrow()->save_state() == weights);
  user(*s, "ana");
  CHECK(status(*s, "pick 4 items") == "induced");
  const Json rules = s->handle({{"op", "rules"}});
  REQUIRE(rules["rules"].size() >= 1);
  int uses = 0;  // the accepted derivation used one of the definition's rules, once
  for (const auto& r : rules["rules"]) uses += r["uses_by_author"].get<int>();
  CHECK(uses == 1);
  // New rules continue the id sequence instead of reusing ids.
  const Json more = define(*s, "go west", {"move left"});
  REQUIRE(more["rules"].size() == 1);
  for (const auto& r : rules["rules"]) CHECK(r["id"] != more["rules"][0]["id"]);
}

TEST_CASE("a preload file is replayed once through induction", "[naturalize]") {
  const std::string store = scratch_path("lex") + ".sqlite";
  const std::string preload = scratch_path("preload") + ".jsonl";
  {
    std::ofstream out(preload);
    out << R"({"head":"go west","body":["move left"],"author":"expert"})"
        << "\n"
        << R"({"head":"move left","body":["move right"],"author":"expert"})"
        << "\n"
        << R"({"head":"gather red","body":["foreach point in world containing item is red {visit point; pick every item is red}"],"author":"expert"})"
        << "\n";
  }
  for (int start = 0; start < 2; ++start) {
    auto s = open(store, {"lexicon.preload=" + preload});
    user(*s, "ana");
    CHECK(status(*s, "go west") == "induced");
    CHECK(status(*s, "gather blue") == "induced");
    const Json rules = s->handle({{"op", "rules"}, {"author", "expert"}});
    CHECK(rules["rules"].size() >= 2);
  }
  naturalization::LexiconStore reopened(store);
  CHECK(reopened.definitions().size() == 2);  // the core head failed; no replay on restart
}

TEST_CASE("define generalizes a too specific body before inducing", "[naturalize]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  Json world = s->handle({{"op", "state"}})["world"];
  world["robot"]["x"] = 9;
  world["robot"]["y"] = 8;
  REQUIRE(s->handle({{"op", "world"}, {"world", world}})["ok"] == true);
  user(*s, "ana");
  const Json a = define(*s, "visit red triangle", {"move right"});
  REQUIRE(a["ok"] == true);
  CHECK(a["generalized"] == "{visit {world containing item {{is red} and {is triangle}}}}");
  REQUIRE(a.contains("discarded"));
  bool rewriting = false;
  for (const auto& r : a["rules"]) rewriting = rewriting || r["how"] == "rewriting";
  CHECK(rewriting);
  const Json q = s->handle({{"op", "query"}, {"text", "visit blue circle"}});
  REQUIRE(q["status"] == "induced");
  CHECK(q["candidates"][0]["formula"] ==
        "{visit {world containing item {{is blue} and {is circle}}}}");
}

TEST_CASE("per-user weights: each user's accepts train only their own model", "[naturalize]") {
  const std::string store = scratch_path("lex") + ".sqlite";
  auto s = open(store, {"lexicon.weights=per_user"});
  const std::string initial = s->runtime().scorer.borrow()->save_state();
  user(*s, "ana");
  const Json q = s->handle({{"op", "query"}, {"text", "pick item not is red and is green"}});
  REQUIRE(q["candidates"].size() >= 2);
  REQUIRE(s->handle({{"op", "accept"}, {"rank", 1}})["ok"] == true);
  const std::string ana = s->runtime().scorer.borrow()->save_state();
  CHECK(ana != initial);
  // The scorer keeps a partition per user (its per_user param, which lexicon.weights = per_user
  // sets): ana's alone learnt, and switching user swaps nothing.
  const Json models = Json::parse(ana)["models"];
  REQUIRE(models.size() == 1);
  REQUIRE(models.contains("ana"));
  user(*s, "bob");
  CHECK(s->runtime().scorer.borrow()->save_state() == ana);
  // Stored under the one weights key, partition ana, each equal to ana's model.
  naturalization::LexiconStore reopened(store);
  const auto stored = reopened.weight_changes(naturalization::kWeightsKey);
  REQUIRE(stored.size() == models["ana"].size());
  for (const auto& c : stored) {
    CHECK(c.model == "ana");
    CHECK(models["ana"][c.feature][0].get<double>() == c.weight);
    CHECK(models["ana"][c.feature][1].get<double>() == c.aux);
  }
  CHECK(reopened.weight_changes("user:ana").empty());
  CHECK(reopened.legacy_user_weight_keys() == 0);
  CHECK_FALSE(reopened.load_weights(naturalization::kWeightsKey));
}

namespace {
// Forwards to the real scorer and records what the kernel put in the contexts it was given.
class RecordingScorer : public sdk::Scorer {
 public:
  explicit RecordingScorer(std::shared_ptr<sdk::Scorer> real) : real_(std::move(real)) {}
  mutable bool scored_with_usage = false;
  mutable std::uint64_t most_uses_by_others = 0;
  bool learned_with_usage = false;

 protected:
  double do_score_node(const sdk::Derivation& n, const sdk::ScoreContext& ctx) const override {
    if (ctx.usage != nullptr && n.rule) {
      scored_with_usage = true;
      most_uses_by_others = std::max(most_uses_by_others, ctx.usage->uses(n.rule->id).by_others);
    }
    return real_->score_node(n, ctx);
  }
  void do_features(const sdk::Derivation& n, const sdk::ScoreContext& ctx,
                   sdk::FeatureVector& out) const override {
    real_->features(n, ctx, out);
  }
  void do_learn(const std::vector<sdk::Candidate>& c, std::size_t accepted,
                const sdk::ScoreContext& ctx) override {
    learned_with_usage = ctx.usage != nullptr;
    real_->learn(c, accepted, ctx);
  }
  std::string do_save_state() const override { return real_->save_state(); }
  void do_load_state(std::string_view state) override { real_->load_state(state); }

 private:
  std::shared_ptr<sdk::Scorer> real_;
};
}  // namespace

TEST_CASE("scorers read the kernel's use counts from their context", "[naturalize]") {
  auto s = open(scratch_path("lex") + ".sqlite");
  kernel::Runtime& rt = s->runtime();
  auto recording = std::make_shared<RecordingScorer>(rt.scorer.shared());
  rt.scorer = kernel::PluginRef<sdk::Scorer>(recording, rt.scorer.id());
  user(*s, "ana");
  define(*s, "go west", {"move left"});
  user(*s, "bob");
  REQUIRE(status(*s, "go west") == "induced");
  CHECK(recording->scored_with_usage);
  CHECK(recording->most_uses_by_others == 0);
  REQUIRE(s->handle({{"op", "accept"}, {"rank", 0}})["ok"] == true);
  CHECK(recording->learned_with_usage);
  REQUIRE(status(*s, "go west") == "induced");
  CHECK(recording->most_uses_by_others == 1);  // bob's accept of ana's rule, as the table says
}

TEST_CASE("naturalization options start from the kernel schema's defaults",
          "[naturalize][config][defaults]") {
  const sdk::ParamSchema& schema = kernel::Config::schema();
  const auto def = [&](const char* key) {
    const sdk::ParamSpec* spec = schema.find(key);
    REQUIRE(spec != nullptr);
    REQUIRE(spec->default_value.has_value());
    return *spec->default_value;
  };
  const naturalization::NaturalizeOptions o;
  CHECK(o.induction.alignment == std::get<bool>(def("induction.alignment")));
  CHECK(o.generalize == std::get<bool>(def("induction.generalize")));
  CHECK(o.perturbed_checks == std::get<std::int64_t>(def("induction.perturbed_checks")));
  CHECK(o.store.busy_timeout_ms == std::get<std::int64_t>(def("lexicon.busy_timeout_ms")));
  CHECK(o.snapshot_min_rules == std::get<std::int64_t>(def("lexicon.snapshot_min_rules")));
  CHECK(to_string(o.sharing) == std::get<std::string>(def("lexicon.sharing")));
  CHECK(o.induction.alignment_window ==
        (std::get<std::string>(def("induction.alignment_mode")) == "window"));
  CHECK(o.induction_sees_everyone == (std::get<std::string>(def("induction.view")) == "everyone"));
}

TEST_CASE("induction.view=everyone: a private run's definitions see every user's rules",
          "[naturalize]") {
  // feb2018/groupB1#494 (docs/naturalization.md §4.1): in the 2018 server's private run BP2's
  // `visit empty space` packed BP4's `visit empty`, giving `$Action space`.
  const std::string empty = "visit world minus {world containing item}";
  auto rhs_of = [](const Json& answer) {
    std::vector<std::string> out;
    for (const auto& r : answer["rules"]) {
      std::string text;
      for (const auto& sym : r["rhs"]) text += (text.empty() ? "" : " ") + sym.get<std::string>();
      out.push_back(text);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  for (const std::string view : {"author", "everyone"}) {
    INFO("induction.view=" << view);
    auto s = open(scratch_path("view-" + view) + ".sqlite",
                  {"lexicon.sharing=private", "induction.view=" + view});
    user(*s, "bp4");
    REQUIRE(define(*s, "visit empty", {empty})["ok"] == true);
    user(*s, "bp2");
    const Json a = define(*s, "visit empty space", {empty});
    REQUIRE(a["ok"] == true);
    if (view == "author")
      CHECK(rhs_of(a) == std::vector<std::string>{"visit empty space"});
    else
      CHECK(rhs_of(a) == std::vector<std::string>{"$Action space", "visit empty space"});
    // Parses stay private either way: bp2 cannot read bp4's phrase.
    CHECK(status(*s, "visit empty") == "unparsable");
  }
}
