// Matches, packings, rule construction and alignment on hand-built charts (no parser).
#include <catch2/catch.hpp>

#include "flipper/naturalization/induction.hpp"
#include "flipper/sdk/canonical.hpp"
#include "synthetic_chart.hpp"

using namespace flipper;
using flipper::testsupport::node;
using K = sdk::Kind;

namespace {

sdk::Program num(double v) {
  return sdk::make_num(v);
}
sdk::Program color(const char* c) {
  return sdk::make_word(K::Color, c);
}
sdk::Program shape(const char* s) {
  return sdk::make_word(K::Shape, s);
}
sdk::Program item() {
  return sdk::make(K::Item);
}
sdk::Program pick(sdk::Program i) {
  return sdk::make(K::Pick, {std::move(i)});
}
sdk::Program drop(sdk::Program i) {
  return sdk::make(K::Drop, {std::move(i)});
}
sdk::Program repeat(sdk::Program n, sdk::Program body) {
  return sdk::make(K::Repeat, {std::move(n), std::move(body)});
}
sdk::Program is(sdk::Program word) {
  return sdk::make(K::FilterIs, {std::move(word)});
}
sdk::Program item_is(sdk::Program filter) {
  return sdk::make(K::Item, {std::move(filter)});
}

std::vector<std::string> rhs_text(const sdk::Rule& r) {
  std::vector<std::string> out;
  for (const auto& s : r.rhs) out.push_back(s.text);
  return out;
}

}  // namespace

TEST_CASE("matches keep one best derivation per span, category and program", "[induction]") {
  const auto body = repeat(num(3), pick(item()));
  const std::vector<sdk::DerivationPtr> chart = {
      node("$Number.token", 1, 2, num(3), 1.0),
      node("$Numbers", 1, 2, num(3), 2.5),  // normalises to $Number: same match
      node("$Number", 0, 1, num(4), 9.0),   // not in the body
      node("$Item", 2, 3, item(), 1.0),     // `items` read as item: in the body
      node("$Action", 0, 3, pick(item())),  // whole head: never a match
  };
  const auto m = naturalization::find_matches(chart, body, 3);
  REQUIRE(m.size() == 2);
  CHECK(m[0].start == 1);
  CHECK(m[0].category == "$Number");
  CHECK(m[0].score == 2.5);
  CHECK(m[1].category == "$Item");
}

TEST_CASE("simple packing takes core-only one-token primitive matches", "[induction]") {
  std::vector<naturalization::Match> m = {
      {0, 2, "$Item", item(), 3, true},          // two tokens: not simple
      {1, 2, "$Color", color("red"), 1, false},  // induced: not simple
      {2, 3, "$Number", num(3), 1, true},
      {3, 4, "$PropertySet", is(shape("circle")), 1, true},  // not primitive
      {4, 5, "$Shape", shape("circle"), 1, true},
  };
  const auto p = naturalization::simple_packing(m);
  REQUIRE(p.size() == 2);
  CHECK(p[0].category == "$Number");
  CHECK(p[1].category == "$Shape");
}

TEST_CASE("best packing: non-overlapping, maximal, greatest total", "[induction]") {
  SECTION("two small spans beat one large") {
    std::vector<naturalization::Match> m = {{0, 3, "$Area", item(), 4, true},
                                            {0, 1, "$Color", color("red"), 3, true},
                                            {2, 3, "$Shape", shape("circle"), 3, true}};
    const auto p = naturalization::best_packing(m, 3);
    REQUIRE(p.size() == 2);
    CHECK(naturalization::packing_score(p) == 6);
  }
  SECTION("a large span beats two small") {
    std::vector<naturalization::Match> m = {{0, 3, "$Area", item(), 7, true},
                                            {0, 1, "$Color", color("red"), 3, true},
                                            {2, 3, "$Shape", shape("circle"), 3, true}};
    const auto p = naturalization::best_packing(m, 3);
    REQUIRE(p.size() == 1);
    CHECK(p[0].end == 3);
  }
  SECTION("maximal even when scores are negative") {
    std::vector<naturalization::Match> m = {{0, 1, "$Color", color("red"), -1, true},
                                            {2, 3, "$Shape", shape("circle"), -2, true}};
    const auto p = naturalization::best_packing(m, 4);
    REQUIRE(p.size() == 2);
    CHECK(naturalization::packing_score(p) == -3);
  }
  SECTION("no matches, empty packing") {
    CHECK(naturalization::best_packing({}, 3).empty());
  }
}

TEST_CASE("best packing ties: parts win only when several body statements share them",
          "[induction]") {
  // Totals are equal (an induced phrase scores what its parts score): the whole phrase
  // [0,2) against its parts [0,1) + [1,2), then a token no match covers.
  auto matches = [](int statements) {
    return std::vector<naturalization::Match>{
        {0, 1, "$ItemAct", sdk::make_word(K::ItemAct, "pick"), 1.0, true, statements},
        {0, 2, "$Action", pick(item_is(is(color("green")))), 3.0, false, 1},
        {1, 2, "$Property", color("green"), 2.0, true, statements}};
  };
  SECTION("held by one statement: the whole phrase (pick green item := pick item is green)") {
    const auto p = naturalization::best_packing(matches(1), 3);
    REQUIRE(p.size() == 1);
    CHECK(p[0].category == "$Action");
  }
  SECTION("held by two statements: the parts (walk and grab blue square)") {
    const auto p = naturalization::best_packing(matches(2), 3);
    REQUIRE(p.size() == 2);
    CHECK(p[0].category == "$ItemAct");
    CHECK(p[1].category == "$Property");
  }
  SECTION("one shared part is enough, and a higher total still wins first") {
    auto m = matches(1);
    m[2].statements = 2;
    CHECK(naturalization::best_packing(m, 3).size() == 2);
    m[1].score = 3.5;
    CHECK(naturalization::best_packing(m, 3).size() == 1);
  }
  SECTION("totals within 1e-9 are equal") {
    auto m = matches(2);
    m[1].score = 3.0 + 5e-10;
    CHECK(naturalization::best_packing(m, 3).size() == 2);
    m[1].score = 3.0 + 5e-9;
    CHECK(naturalization::best_packing(m, 3).size() == 1);
  }
}

TEST_CASE("matches count the body statements that hold them", "[induction]") {
  // `walk and grab blue square` := `visit world containing item is blue and is square;
  // pick item is blue and is square`: `blue` and `square` are in both statements.
  const auto filter = sdk::make(K::FilterAnd, {is(color("blue")), is(shape("square"))});
  const auto visit = sdk::make(
      K::VisitArea, {sdk::make(K::AreaContaining, {sdk::make(K::World), item_is(filter)})});
  const auto grab = pick(item_is(filter));
  const auto body = sdk::make_seq({visit, grab});
  const std::vector<sdk::DerivationPtr> chart = {
      node("$Action", 2, 5, grab, 2.0),
      node("$Color", 3, 4, color("blue"), 1.0),
      node("$Shape", 4, 5, shape("square"), 1.0),
      node("$ItemAct", 2, 3, sdk::make_word(K::ItemAct, "pick"), 1.0),
  };
  const auto m = naturalization::find_matches(chart, body, 5);
  REQUIRE(m.size() == 4);  // ordered by (start, end)
  CHECK(m[0].category == "$ItemAct");
  CHECK(m[0].statements == 1);  // the verb of the pick (full form) only: the visit has none
  CHECK(m[1].category == "$Action");
  CHECK(m[1].statements == 1);
  CHECK(m[2].category == "$Color");
  CHECK(m[2].statements == 2);
  CHECK(m[3].category == "$Shape");
  CHECK(m[3].statements == 2);
  // A body that is no sequence is one statement.
  for (const auto& x : naturalization::find_matches(chart, grab, 5)) CHECK(x.statements == 1);
}

TEST_CASE("rule construction replaces every equal subtree by the match's hole", "[induction]") {
  // `red to room1` := `pick item is red; drop item is red` (made-up body with `red` twice)
  const auto body =
      sdk::make_seq({pick(item_is(is(color("red")))), drop(item_is(is(color("red"))))});
  const std::vector<std::string> head = {"red", "to", "room1"};
  const std::vector<naturalization::Match> packing = {{0, 1, "$Color", color("red"), 1, true}};
  auto built = naturalization::build_rule("$Action", head, packing, body, sdk::RuleOrigin::best);
  REQUIRE(built.rule);
  CHECK(rhs_text(*built.rule) == std::vector<std::string>{"$Color", "to", "room1"});
  CHECK(sdk::render(built.rule->sem) == "{{pick item {is $1}};{drop item {is $1}}}");
  CHECK(built.rule->how == sdk::RuleOrigin::best);
  CHECK(sdk::equal(
      sdk::substitute(built.rule->sem, {color("blue")}),
      sdk::make_seq({pick(item_is(is(color("blue")))), drop(item_is(is(color("blue"))))})));
}

TEST_CASE("equal packed spans share one hole", "[induction]") {
  const auto body = repeat(num(2), pick(item()));
  const std::vector<std::string> head = {"2", "and", "2"};
  const std::vector<naturalization::Match> packing = {{0, 1, "$Number", num(2), 1, true},
                                                      {2, 3, "$Number", num(2), 1, true}};
  auto built = naturalization::build_rule("$Action", head, packing, body, sdk::RuleOrigin::best);
  REQUIRE(built.rule);
  CHECK(rhs_text(*built.rule) == std::vector<std::string>{"$Number", "and", "$Number"});
  CHECK(sdk::render(built.rule->sem) == "{repeat $1 times {pick item }}");
}

TEST_CASE("rules with a single category or more than four are rejected", "[induction]") {
  const auto body = pick(item_is(is(color("red"))));
  auto single = naturalization::build_rule(
      "$Action", {"red"}, {{0, 1, "$Color", color("red"), 1, true}}, body, sdk::RuleOrigin::best);
  CHECK_FALSE(single.rule);
  CHECK(single.rejection == naturalization::RuleRejection::single_category);
  std::vector<naturalization::Match> five;
  for (int i = 0; i < 5; ++i) five.push_back({i, i + 1, "$Color", color("red"), 1, true});
  auto many = naturalization::build_rule("$Action", {"a", "b", "c", "d", "e"}, five, body,
                                         sdk::RuleOrigin::best);
  CHECK_FALSE(many.rule);
  CHECK(many.rejection == naturalization::RuleRejection::too_many_categories);
  auto constant =
      naturalization::build_rule("$Action", {"do", "it"}, {}, body, sdk::RuleOrigin::simple);
  REQUIRE(constant.rule);
  CHECK(sdk::render(constant.rule->sem) == sdk::render(body));
}

TEST_CASE("a plain item packed as $CountedItem becomes a hole only under pick/drop",
          "[induction]") {
  const auto body = drop(item());
  auto built = naturalization::build_rule("$Action", {"throw", "item"},
                                          {{1, 2, "$CountedItem", item(), 1, true}}, body,
                                          sdk::RuleOrigin::alignment);
  REQUIRE(built.rule);
  CHECK(sdk::render(built.rule->sem) == "{drop $1}");
  const auto every = sdk::make(K::Every, {item()});
  CHECK(sdk::equal(sdk::substitute(built.rule->sem, {every}), drop(every)));
}

TEST_CASE("alignment maps the differing stretch to the body node's category", "[induction]") {
  SECTION("an exact node: pick all := pick every item") {
    const auto every = sdk::make(K::Every, {item()});
    auto counted = node("$CountedItem", 1, 3, every, 2, {node("$Item", 2, 3, item())});
    auto root = node("$Action", 0, 3, pick(every), 4, {counted});
    const auto rules =
        naturalization::alignment_rules({"pick", "all"}, {"pick", "every", "item"}, root);
    REQUIRE(rules.size() == 1);
    CHECK(rules[0].lhs == "$CountedItem");
    CHECK(rhs_text(rules[0]) == std::vector<std::string>{"all"});
    CHECK(sdk::render(rules[0].sem) == "every item ");
    CHECK(rules[0].how == sdk::RuleOrigin::alignment);
  }
  SECTION("no exact node: throw item := drop item") {
    auto kid = node("$CountedItem.act", 1, 2, item(), 2, {node("$CountedItem", 1, 2, item())});
    auto root = node("$Action", 0, 2, drop(item()), 3, {kid});
    const auto rules = naturalization::alignment_rules({"throw", "item"}, {"drop", "item"}, root);
    REQUIRE(rules.size() == 1);
    CHECK(rules[0].lhs == "$Action");
    CHECK(rhs_text(rules[0]) == std::vector<std::string>{"throw", "$CountedItem"});
    CHECK(sdk::render(rules[0].sem) == "{drop $1}");
  }
  SECTION("no anchor token, or a stretch too long: nothing") {
    auto root = node("$Action", 0, 1, drop(item()));
    CHECK(naturalization::alignment_rules({"throw"}, {"drop"}, root).empty());
    CHECK(naturalization::alignment_rules({"a", "b", "c", "d", "e", "f", "x"}, {"g", "x"}, root)
              .empty());
  }
}
