// The toolkit's chart parser used directly (flipper/toolkit/chart_parser.hpp): the candidate order
// of docs/naturalization.md §2 — core first even when an induced reading scores higher, then by
// score, then the newest rule first — and the checks every parse makes (a scorer is required,
// max_tokens at N and N + 1).
#include <catch2/catch.hpp>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/testing/core_scorer.hpp"
#include "flipper/toolkit/chart_parser.hpp"

using namespace flipper;

namespace {

// Every node of an induced rule scores 10, every other node 0 (no core bonus): an induced
// reading outscores the core one.
class FavourInduced final : public testing::CoreScorer {
 protected:
  double do_score_node(const sdk::Derivation& node, const sdk::ScoreContext&) const override {
    return node.rule->induced ? 10.0 : 0.0;
  }
};

std::shared_ptr<const sdk::Grammar> grammar() {
  return std::make_shared<const sdk::Grammar>(sdk::parse_grammar(
      "$ROOT -> $Action => $1\n$Action -> move left => {move left}\n", "order", {}, {}));
}

// `move left` read as `program` by an induced rule created `created`.
sdk::RulePtr induced(const std::string& id, const std::string& program, std::int64_t created) {
  const auto g = sdk::parse_grammar("$Action -> move left => " + program + "\n", id, {}, {});
  auto r = std::make_shared<sdk::Rule>(*g.rules.back());
  r->id = id;
  r->induced = true;
  r->created = created;
  return r;
}

sdk::ParseResult parse(const sdk::Parser& parser, const std::string& text,
                       const sdk::Scorer* scorer) {
  sdk::ParseRequest req;
  req.tokens = sdk::tokenize(text);
  req.scorer = scorer;
  return parser.parse(req);
}

}  // namespace

TEST_CASE("chart parser: core first over a higher-scoring induced reading, then newest first") {
  toolkit::ChartParser parser;
  parser.set_grammar(grammar());
  parser.add_rule(induced("r1", "{move right}", 1));
  parser.add_rule(induced("r2", "{move up}", 2));
  const FavourInduced scorer;
  const auto r = parse(parser, "move left", &scorer);
  REQUIRE(r.candidates.size() == 3);
  CHECK(sdk::render(r.candidates[0].program) == "{move left}");
  CHECK(r.candidates[0].core_only);
  CHECK(r.candidates[0].score == 0.0);
  // Equal scores (10): the newer rule's reading first.
  CHECK(sdk::render(r.candidates[1].program) == "{move up}");
  CHECK(r.candidates[1].score == 10.0);
  CHECK(r.candidates[1].newest_rule == 2);
  CHECK(sdk::render(r.candidates[2].program) == "{move right}");
  // Removing r2 removes its reading, nothing else.
  parser.remove_rule("r2");
  const auto after = parse(parser, "move left", &scorer);
  REQUIRE(after.candidates.size() == 2);
  CHECK(sdk::render(after.candidates[1].program) == "{move right}");
}

TEST_CASE("chart parser: a scorer is required, and max_tokens is the longest input parsed") {
  toolkit::ChartOptions options;
  options.max_tokens = 3;
  toolkit::ChartParser parser(options);
  parser.set_grammar(grammar());
  const FavourInduced scorer;
  try {
    parse(parser, "move left", nullptr);
    FAIL("parsed without a scorer");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kBadRequest);
    CHECK(std::string(e.what()) == "chart parser: the parse request has no scorer");
  }
  CHECK(parse(parser, "move left left", &scorer).candidates.empty());  // 3 tokens: parsed
  try {
    parse(parser, "move left left left", &scorer);
    FAIL("4 tokens parsed with max_tokens = 3");
  } catch (const sdk::Error& e) {
    CHECK(e.code() == sdk::codes::kInputTooLong);
    CHECK(std::string(e.what()) == "chart parser: 4 tokens; the limit is max_tokens = 3");
  }
  CHECK(parse(parser, "", &scorer).candidates.empty());
}
