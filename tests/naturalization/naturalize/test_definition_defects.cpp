// Regression tests of naturalization defects (docs/naturalization.md), each stated on the study map
// (configs/worlds/study2018.json, the default world; the robot starts at [2,4]) through the
// session protocol with the default config (rewrites + wordnet generalization on).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/sdk/canonical.hpp"
#include "naturalize_fixture.hpp"
#include "product_schema.hpp"

using namespace flipper;
using namespace flipper::naturalizetest;
using kernel::Json;

namespace {

Json query(kernel::Session& s, const std::string& text, int k = 10) {
  return s.handle({{"op", "query"}, {"text", text}, {"k", k}});
}

/// Canonical text of a core-language program, as candidates' `formula` print it.
std::string canonical(const std::string& text) {
  return sdk::render(sdk::read_canonical(text));
}

std::vector<std::string> formulas(const Json& answer) {
  std::vector<std::string> out;
  for (const auto& c : answer["candidates"]) out.push_back(c["formula"]);
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

/// Runs a core-language command and accepts it (moves the robot, picks items).
void act(kernel::Session& s, const std::string& text) {
  const Json q = query(s, text, 1);
  REQUIRE(q["status"] == "core");
  REQUIRE(s.handle({{"op", "accept"}, {"rank", 0}})["ok"] == true);
}

std::vector<std::pair<std::string, std::string>> held(const Json& world) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& i : world["robot"]["holding"]) out.emplace_back(i["color"], i["shape"]);
  return out;
}

std::vector<int> robot_at(const Json& world) {
  return {world["robot"]["x"].get<int>(), world["robot"]["y"].get<int>()};
}

}  // namespace

TEST_CASE("a statement hole is $Action, never $ROOT", "[naturalize][defects]") {
  auto s = open(":memory:");
  user(*s, "ana");
  const Json d = define(*s, "move up thrice", {"repeat 3 times move up"});
  REQUIRE(d["ok"] == true);
  bool statement_rule = false;
  for (const auto& r : d["rules"]) {
    for (const auto& sym : r["rhs"]) CHECK(sym != "$ROOT");
    statement_rule = statement_rule || r["rhs"] == Json::array({"$Action", "thrice"});
  }
  CHECK(statement_rule);
  // `$Action thrice` repeats the last statement only, as the original's rule did.
  const auto f = formulas(query(*s, "move left ; move right thrice"));
  CHECK(contains(f, canonical("{{move left};{repeat 3 times {move right}}}")));
  CHECK_FALSE(contains(f, canonical("{repeat 3 times {{move left};{move right}}}")));
}

TEST_CASE("a stored $ROOT rule is not served, the warning says how to re-induce",
          "[naturalize][defects]") {
  const std::string path = scratch_path("root-rule") + ".sqlite";
  {
    naturalization::LexiconStore store(path);
    naturalization::StoredRule r;
    r.id = "r1";
    r.lhs = "$Action";
    r.rhs = {"$ROOT", "thrice"};
    r.semantics = "{repeat 3 times $1}";
    r.author = "ana";
    r.head = "move up thrice";
    r.body = {"repeat 3 times move up"};
    r.how = "best";
    r.created = 1;
    store.add_definition({0, r.head, r.body, "ana", 0}, {r});
  }
  // One bad rule must not lock everyone out of a shared store (the quarantine policy): the
  // store opens, the rule is not served, and the warning names it and the way out.
  std::shared_ptr<kernel::Runtime> rt =
      kernel::make_runtime(kernel::Config::load(std::nullopt, {"lexicon.path=" + path}));
  auto options = naturalization::NaturalizeOptions::from_config(rt->config);
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  auto nat = std::make_shared<naturalization::Naturalizer>(rt, options);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("rule r1") && Catch::Contains("$ROOT") &&
                              Catch::Contains("flipper lexicon import"));
  CHECK(nat->induced_rules().empty());
  auto s = std::make_unique<kernel::Session>(rt);
  naturalization::install_naturalization(*s, nat);
  user(*s, "ana");
  CHECK(status(*s, "move left ; move right thrice") == "unparsable");
}

TEST_CASE("generalization never drops a statement of the body", "[naturalize][defects]") {
  auto s = open(":memory:");
  user(*s, "ana");
  act(*s, "visit [7,4]");  // the green square lies here: the visit leaves no trace step
  const Json d = define(
      *s, "fetch green square",
      {"visit world containing item is green and is square", "pick item is green and is square"});
  REQUIRE(d["ok"] == true);
  for (const auto& r : d["rules"])
    CHECK_THAT(r["semantics"].get<std::string>(), Catch::Contains("visit"));
  // From [2,4] the red circle is at [7,4]: the top reading walks there and picks it.
  act(*s, "visit [2,4]");
  const Json q = query(*s, "fetch red circle");
  REQUIRE(q["status"] == "induced");
  const Json& top = q["candidates"][0];
  CHECK(top["realizable"] == true);
  CHECK(robot_at(top["world"]) == std::vector<int>{7, 4});
  CHECK(held(top["world"]) == std::vector<std::pair<std::string, std::string>>{{"red", "circle"}});
}

TEST_CASE(
    "a rewriting does not narrow the meaning with a colour the definition "
    "never mentions",
    "[naturalize][defects]") {
  auto s = open(":memory:");
  user(*s, "ana");
  // Hold only blue items: the blue circles of [3,8] and [7,4].
  act(*s, "visit [3,8]; pick item is blue; visit [7,4]; pick item is blue");
  const Json d = define(*s, "drop the lot", {"drop every item"});
  REQUIRE(d["ok"] == true);
  if (!d["generalized"].is_null())
    CHECK_THAT(d["generalized"].get<std::string>(), !Catch::Contains("blue"));
  for (const auto& r : d["rules"])
    CHECK_THAT(r["semantics"].get<std::string>(), !Catch::Contains("blue"));
  // At [7,4] a red circle, a green square and a green circle lie: `pick the lot` takes all three.
  const Json q = query(*s, "pick the lot");
  REQUIRE(q["status"] == "induced");
  const Json& top = q["candidates"][0];
  CHECK(top["realizable"] == true);
  CHECK(held(top["world"]).size() == 5);
}

TEST_CASE("best packing generalizes matched phrases together", "[naturalize][defects]") {
  auto s = open(":memory:");
  user(*s, "ana");
  REQUIRE(define(*s, "grab blue square", {"pick item is blue and is square"})["ok"] == true);
  const Json d = define(*s, "walk and grab blue square",
                        {"visit world containing item is blue and is square", "grab blue square"});
  REQUIRE(d["ok"] == true);
  // From [2,4]: the red circle lies at [7,4] (the blue square at [11,1]).
  const Json q = query(*s, "walk and grab red circle");
  REQUIRE(q["status"] == "induced");
  const Json& top = q["candidates"][0];
  CHECK(top["formula"] == canonical("{{visit {world containing item {{is red} and {is circle}}}};"
                                    "{pick item {{is red} and {is circle}}}}"));
  CHECK(top["realizable"] == true);
  CHECK(robot_at(top["world"]) == std::vector<int>{7, 4});
  CHECK(held(top["world"]) == std::vector<std::pair<std::string, std::string>>{{"red", "circle"}});
}
