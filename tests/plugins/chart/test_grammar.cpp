// Grammar files: the core grammar loads; bad lines give bad_grammar naming the line.
#include <catch2/catch.hpp>

#include "flipper/sdk/errors.hpp"
#include "parse_support.hpp"

using namespace flipper;

TEST_CASE("core grammar loads with the original's categories") {
  auto g = parsetest::core_grammar();
  CHECK(g->rules.size() > 80);
  CHECK(g->root == "$ROOT");
  CHECK(g->directions.size() == 4);
  for (const auto& r : g->rules) {
    CHECK(r->id.rfind("core:", 0) == 0);
    CHECK_FALSE(r->induced);
    CHECK_NOTHROW(sdk::category_sort(r->lhs));
  }
  CHECK(sdk::describe(*g->rules.front()) == "$ROOT -> $Actions => $1");
}

TEST_CASE("categories: sorts and normalisation") {
  CHECK(sdk::category_sort("$Areas") == sdk::Sort::Area);
  CHECK(sdk::category_sort("$AreaList") == sdk::Sort::Collection);
  CHECK(sdk::category_sort("$Number.token") == sdk::Sort::Number);
  CHECK(sdk::normalize_category("$Actions") == "$Action");
  CHECK(sdk::normalize_category("$AreaCollections") == "$AreaCollection");
  CHECK(sdk::normalize_category("$Color.property") == "$Color");
  CHECK(sdk::normalize_category("$Point") == "$Point");
  CHECK_THROWS_AS(sdk::category_sort("$Nope"), sdk::Error);
}

TEST_CASE("bad grammar lines are rejected with the line number") {
  auto bad = [](const std::string& text, const std::string& needle) {
    try {
      sdk::parse_grammar(text, "g.grammar", {"red"}, {"circle"});
      FAIL("no error for: " << text);
    } catch (const sdk::Error& e) {
      CHECK(e.code() == sdk::codes::kBadGrammar);
      CHECK_THAT(e.what(), Catch::Contains(needle));
    }
  };
  bad("$Action -> move $Direction", "g.grammar:1: missing '=> template'");
  bad("# c\n$Nope -> x => world", "g.grammar:2");
  bad("Action -> x => current", "not a category");
  bad("$Point -> here => world", "bad template");
  bad("$Number -> foo @number", "whole right-hand side");
  bad("$Color -> @shape", "cannot yield");
  bad("", "no rules");
  CHECK_THROWS_AS(sdk::load_grammar_file("/no/such.grammar", {}, {}), sdk::Error);
}

TEST_CASE("token classes and rule meanings") {
  auto g = parsetest::core_grammar();
  CHECK(sdk::class_matches(*g, sdk::Symbol::Type::color, "grey"));
  CHECK(sdk::class_matches(*g, sdk::Symbol::Type::number, "-99"));
  CHECK_FALSE(sdk::class_matches(*g, sdk::Symbol::Type::number, "1e1"));
  CHECK_FALSE(sdk::class_matches(*g, sdk::Symbol::Type::direction, "forward"));
  auto g3 = sdk::parse_grammar("$Direction -> @direction", "d", {}, {}, {"Ascend"});
  CHECK(sdk::class_matches(g3, sdk::Symbol::Type::direction, "ascend"));
  CHECK(sdk::render(sdk::apply_rule(*g3.rules[0], {}, "ascend")) == "ascend");
}
