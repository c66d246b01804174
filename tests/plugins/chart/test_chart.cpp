// Chart parser behaviour: conformance kit, induced rules (incremental add/remove, visibility,
// ordering core-first), head charts, beam, stop condition, ranking after accepts.
#include <catch2/catch.hpp>
#include <functional>
#include <sstream>

#include "flipper/sdk/errors.hpp"
#include "flipper/testing/parser_conformance.hpp"
#include "parse_support.hpp"

using namespace flipper;

namespace {

sdk::RulePtr induced(const std::string& id, const std::string& lhs, const std::string& rhs,
                     const std::string& tmpl, std::int64_t created,
                     const std::string& author = "bob") {
  auto r = std::make_shared<sdk::Rule>();
  r->id = id;
  r->lhs = lhs;
  std::vector<sdk::Sort> holes;
  std::string w;
  std::istringstream in(rhs);
  while (in >> w) {
    sdk::Symbol s;
    s.text = w;
    s.type = w[0] == '$' ? sdk::Symbol::Type::category : sdk::Symbol::Type::token;
    if (s.type == sdk::Symbol::Type::category) holes.push_back(sdk::category_sort(w));
    r->rhs.push_back(s);
  }
  r->sem = sdk::read_template(tmpl, sdk::category_sort(lhs), holes);
  r->induced = true;
  r->how = sdk::RuleOrigin::best;
  r->author = author;
  r->created = created;
  return r;
}

sdk::ParseResult parse_with(const sdk::Parser& p, const sdk::Scorer& s, const std::string& u,
                            std::function<void(sdk::ParseRequest&)> tweak = {}) {
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize(u);
  req.scorer = &s;
  req.context.user = "alice";
  if (tweak) tweak(req);
  return p.parse(req);
}

}  // namespace

TEST_CASE("chart parser passes the parser conformance kit") {
  auto& st = parsetest::shared_stack();
  testing::check_parser_conformance(
      *st.parser, *st.scorer,
      {"move left", "visit world containing item is red ; pick item is red",
       "if possible move left ; move right", "repeat {3 - 1} times { pick item ; move left }",
       "foreach point in [[1,4],[3,4]] { visit point }", "visit room1 or room2 containing item",
       "pick every item has color red and has shape square"});
}

TEST_CASE("trailing semicolon and possible (§3.1)") {
  auto& st = parsetest::shared_stack();
  auto r = st.parse("if possible move left ; move right");
  REQUIRE(r.candidates.size() == 1);
  CHECK(sdk::render(r.candidates[0].program) == "{if {possible {move left}} {move right}}");
  r = st.parse("if robot has item drop item ; move up");
  REQUIRE(r.candidates.size() == 1);
  CHECK(r.candidates[0].program->kind == sdk::Kind::Seq);
  r = st.parse("strict move left ;");  // two derivations, one program
  REQUIRE(r.candidates.size() == 1);
  CHECK(r.candidates[0].derivations.size() == 2);
}

TEST_CASE("induced rules: incremental add and remove, core first, visibility, status") {
  auto parser = testsupport::load_plugin<sdk::Parser>("chart");
  auto scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");
  parser->set_grammar(parsetest::core_grammar());
  CHECK(parse_with(*parser, *scorer, "pick 3 items").candidates.empty());
  parser->add_rule(
      induced("r1", "$Action", "pick $Number items", "{repeat $1 times {pick item}}", 1));
  auto r = parse_with(*parser, *scorer, "pick 3 items");
  REQUIRE(r.candidates.size() == 1);
  CHECK_FALSE(r.candidates[0].core_only);
  CHECK(r.candidates[0].newest_rule == 1);
  CHECK(sdk::render(r.candidates[0].program) == "{repeat 3 times {pick item }}");
  // Used inside core constructs too.
  r = parse_with(*parser, *scorer, "pick 2 items ; move left");
  REQUIRE(r.candidates.size() == 1);
  // A rule that gives core text another meaning never displaces the core reading.
  parser->add_rule(induced("r2", "$Action", "move left", "{move right}", 2));
  r = parse_with(*parser, *scorer, "move left");
  REQUIRE(r.candidates.size() == 2);
  CHECK(r.candidates[0].core_only);
  CHECK(sdk::render(r.candidates[1].program) == "{move right}");
  // Visibility (sharing modes).
  const auto core_only = [](const sdk::Rule& x) { return !x.induced; };
  r = parse_with(*parser, *scorer, "pick 3 items",
                 [&](sdk::ParseRequest& q) { q.visible = sdk::RuleFilter::of(core_only); });
  CHECK(r.candidates.empty());
  // Newer rule first on equal scores.
  parser->add_rule(
      induced("r3", "$Action", "pick $Number items", "{repeat $1 times {pick every item}}", 3));
  r = parse_with(*parser, *scorer, "pick 3 items");
  REQUIRE(r.candidates.size() == 2);
  CHECK(r.candidates[0].newest_rule == 3);
  parser->remove_rule("r3");
  parser->remove_rule("r1");
  parser->remove_rule("no-such-rule");
  CHECK(parse_with(*parser, *scorer, "pick 3 items").candidates.empty());
}

TEST_CASE("head chart: every derivation of every proper sub-span") {
  auto& st = parsetest::shared_stack();
  auto r = parse_with(*st.parser, *st.scorer, "pick 3 red items", [](sdk::ParseRequest& q) {
    q.want_chart = true;
    q.whole_span = false;
  });
  CHECK(r.candidates.empty());
  bool number = false, color = false;
  for (const auto& d : r.chart) {
    CHECK((d->end - d->start) < 4);
    if (sdk::normalize_category(d->category()) == "$Number" && d->start == 1) number = true;
    if (d->category() == "$Color" && d->start == 2) color = true;
  }
  CHECK(number);
  CHECK(color);
}

TEST_CASE("beam and stop condition") {
  auto& st = parsetest::shared_stack();
  const std::string u =
      "visit rooms minus rooms containing item is red minus rooms containing item is blue";
  auto full = parse_with(*st.parser, *st.scorer, u);
  CHECK(full.candidates.size() == 5);
  auto narrow = parse_with(*st.parser, *st.scorer, u, [](sdk::ParseRequest& q) { q.beam = 1; });
  CHECK(narrow.candidates.size() >= 1);
  CHECK(narrow.candidates.size() < full.candidates.size());
  auto stopped = parse_with(*st.parser, *st.scorer, u,
                            [](sdk::ParseRequest& q) { q.stop.max_expansions = 1; });
  CHECK(stopped.stopped);
  CHECK_FALSE(full.stopped);
}

TEST_CASE("ranking changes after accepts in the chosen direction") {
  auto parser = testsupport::load_plugin<sdk::Parser>("chart");
  auto scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");
  parser->set_grammar(parsetest::core_grammar());
  const std::string u = "pick item not is red and is green";
  auto r = parse_with(*parser, *scorer, u);
  REQUIRE(r.candidates.size() == 2);
  CHECK(r.candidates[0].score == r.candidates[1].score);
  const sdk::Program second = r.candidates[1].program;
  sdk::ScoreContext ctx;
  ctx.user = "alice";
  const auto tokens = sdk::tokenize(u);
  ctx.tokens = &tokens;  // span and context features need the utterance
  scorer->learn(r.candidates, 1, ctx);
  r = parse_with(*parser, *scorer, u);
  CHECK(sdk::equal(r.candidates[0].program, second));
  CHECK(r.candidates[0].score > r.candidates[1].score);
  // A similar utterance follows the same preference (`not` over the whole chain vs. the first).
  auto r2 = parse_with(*parser, *scorer, "drop item not is blue and is circle");
  REQUIRE(r2.candidates.size() == 2);
  CHECK(r2.candidates[0].program->kids[0]->kids[0]->kids[0]->kind ==
        second->kids[0]->kids[0]->kids[0]->kind);
}

// Regression: a define head of 65,535 tokens wrapped the chart's int index (out-of-bounds write).
// The kernel refuses long inputs first (input.max_tokens); the parser keeps its own bound, for
// callers that are not the kernel.
TEST_CASE("more tokens than max_tokens (default 4096) are input_too_long") {
  auto& st = parsetest::shared_stack();
  std::string words = "move";
  for (int i = 1; i < 65535; ++i) words += " left";
  try {
    st.parse(words);
    FAIL("a 65,535-token parse was accepted");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kInputTooLong);
    CHECK(std::string(e.what()) == "chart parser: 65535 tokens; the limit is max_tokens = 4096");
  }
}
