// The floating parser: the parser conformance kit through the kernel loader, skipped words as
// nodes with a feature and a cost, exact readings first and never disturbed, bounds (max_skips,
// stop condition), head charts exact only, induced rules.
#include <catch2/catch.hpp>
#include <sstream>

#include "flipper/testing/parser_conformance.hpp"
#include "kernel_loaded.hpp"

using namespace flipper;
using floatingtest::FloatingStack;
using floatingtest::skipped_words;

namespace {

FloatingStack& shared() {
  static FloatingStack s;
  return s;
}

std::string top(const sdk::ParseResult& r) {
  return r.candidates.empty() ? "(none)" : sdk::render(r.candidates.front().program);
}

}  // namespace

TEST_CASE("floating passes the parser conformance kit (kernel-loaded)") {
  auto& st = shared();
  testing::check_parser_conformance(
      *st.parser, *st.scorer,
      {"move left", "visit world containing item is red ; pick item is red",
       "if possible move left ; move right", "repeat {3 - 1} times { pick item ; move left }",
       "foreach point in [[1,4],[3,4]] { visit point }", "visit room1 or room2 containing item",
       "pick every item has color red and has shape square"});
}

TEST_CASE("extra words get the core reading, below every exact one") {
  auto& st = shared();
  // Words around a command (the root wrapped out), and words inside it (a gap before a kid).
  auto r = st.parse("please visit room1 now");
  REQUIRE_FALSE(r.candidates.empty());
  CHECK(top(r) == "{visit room1}");
  CHECK_FALSE(r.candidates[0].core_only);  // a floating reading is not core
  CHECK(skipped_words(*r.candidates[0].derivations[0]) == 2);
  // The core reading's score minus the cost (1 per word, and no core bonus on the 2 skip nodes).
  const double exact = st.parse("visit room1").candidates.at(0).score;
  CHECK(r.candidates[0].score == Approx(exact - 2.0));

  r = st.parse("could you pick the red item");
  REQUIRE_FALSE(r.candidates.empty());
  // The core language has no adjectives before `item`: skipping leaves `pick item` (4 words).
  CHECK(top(r) == "{pick item }");
  CHECK(skipped_words(*r.candidates[0].derivations[0]) == 4);

  r = st.parse("visit room1 and then room2");  // a gap between `and` and its kid
  REQUIRE_FALSE(r.candidates.empty());
  CHECK(top(r) == "{visit {room1 and room2}}");

  // Exact core input: the exact reading first, floating ones (fewer words) after it.
  r = st.parse("visit room1 ; pick item");
  REQUIRE(r.candidates.size() >= 2);
  CHECK(r.candidates[0].core_only);
  CHECK(top(r) == "{{visit room1};{pick item }}");
  CHECK(skipped_words(*r.candidates[0].derivations[0]) == 0);
  for (std::size_t i = 1; i < r.candidates.size(); ++i) {
    CHECK_FALSE(r.candidates[i].core_only);
    CHECK(r.candidates[i].score < r.candidates[0].score);
  }
}

TEST_CASE("each skipped word is a node with its own feature") {
  auto& st = shared();
  auto r = st.parse("please visit room1");
  REQUIRE_FALSE(r.candidates.empty());
  const auto& root = *r.candidates[0].derivations[0];
  REQUIRE(root.rule->id == "floating:skip:please");
  CHECK(root.start == 0);
  CHECK(root.end == 3);
  REQUIRE(root.kids.size() == 1);
  CHECK(root.kids[0]->start == 1);
  CHECK(root.kids[0]->rule->lhs == "$ROOT");
  CHECK_FALSE(root.rule->induced);
  const std::vector<std::string> tokens = {"please", "visit", "room1"};
  sdk::FeatureVector f;
  st.scorer->features(root, {&tokens, "u"}, f);
  bool has_word = false;
  for (const auto& [name, v] : f) has_word = has_word || name == "rule=floating:skip:please";
  CHECK(has_word);
}

TEST_CASE("bounds: max_skips, words only, skip_cost") {
  FloatingStack none({"parser.params.max_skips=0"});
  CHECK(none.parse("please visit room1 now").candidates.empty());
  FloatingStack one({"parser.params.max_skips=1"});
  CHECK(one.parse("please visit room1 now").candidates.empty());  // needs 2
  CHECK(top(one.parse("please visit room1")) == "{visit room1}");
  auto& st = shared();
  // Brackets, separators and numbers carry structure: never skipped.
  CHECK(st.parse("} move left {").candidates.empty());
  CHECK(st.parse("move left 5").candidates.empty());
  CHECK(st.parse("please please please please please visit room1").candidates.empty());  // 5
  FloatingStack costly({"parser.params.skip_cost=10"});
  const double exact = st.parse("visit room1").candidates.at(0).score;
  CHECK(costly.parse("please visit room1").candidates.at(0).score == Approx(exact - 10.0));
}

TEST_CASE("max_skips=0 parses exactly as chart, exact candidates are chart's") {
  auto& chart = parsetest::shared_stack();
  FloatingStack none({"parser.params.max_skips=0"});
  auto& st = shared();
  for (const std::string u :
       {"visit room1 ; pick item", "if possible move left ; move right", "strict move left ;",
        "visit world containing item is red or is blue ; pick every item is red",
        "repeat {3 - 1} times { pick item ; move left }"}) {
    INFO(u);
    const auto c = chart.parse(u), n = none.parse(u), f = st.parse(u);
    REQUIRE(c.candidates.size() == n.candidates.size());
    for (std::size_t i = 0; i < c.candidates.size(); ++i) {
      CHECK(sdk::equal(c.candidates[i].program, n.candidates[i].program));
      CHECK(c.candidates[i].score == n.candidates[i].score);
      CHECK(c.candidates[i].derivations.size() == n.candidates[i].derivations.size());
      // With floating on, the exact candidates come first, unchanged.
      REQUIRE(i < f.candidates.size());
      CHECK(sdk::equal(c.candidates[i].program, f.candidates[i].program));
      CHECK(c.candidates[i].score == f.candidates[i].score);
    }
    CHECK(c.derivations == n.derivations);
  }
}

TEST_CASE("head charts hold exact derivations only, induced rules float too") {
  auto& st = shared();
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize("please pick 3 items now");
  req.scorer = st.scorer.get();
  req.want_chart = true;
  req.whole_span = false;
  const auto head = st.parser->parse(req);
  REQUIRE_FALSE(head.chart.empty());
  for (const auto& d : head.chart) CHECK(skipped_words(*d) == 0);

  FloatingStack fresh;
  auto rule = std::make_shared<sdk::Rule>();
  rule->id = "r1";
  rule->lhs = "$Action";
  for (const std::string w : {"pick", "$Number", "items"})
    rule->rhs.push_back({w[0] == '$' ? sdk::Symbol::Type::category : sdk::Symbol::Type::token, w});
  rule->sem =
      sdk::read_template("{repeat $1 times {pick item}}", sdk::Sort::Action, {sdk::Sort::Number});
  rule->induced = true;
  rule->how = sdk::RuleOrigin::best;
  rule->author = "bob";
  rule->created = 1;
  fresh.parser->add_rule(rule);
  auto r = fresh.parse("please pick 3 items now");
  REQUIRE_FALSE(r.candidates.empty());
  CHECK(top(r) == "{repeat 3 times {pick item }}");
  CHECK(fresh.parse("pick 3 items").candidates.at(0).score >
        r.candidates[0].score);  // the exact induced reading scores higher
  fresh.parser->remove_rule("r1");
  CHECK(fresh.parse("please pick 3 items now").candidates.empty());
}

TEST_CASE("the stop condition ends a floating parse") {
  auto& st = shared();
  std::string u = "visit room1";
  for (int i = 0; i < 20; ++i) u += " ; please visit room2 or room3 now";
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize(u);
  req.scorer = st.scorer.get();
  req.stop.max_expansions = 1000;
  const auto r = st.parser->parse(req);
  CHECK(r.stopped);
  CHECK(r.derivations < 1200);
}
