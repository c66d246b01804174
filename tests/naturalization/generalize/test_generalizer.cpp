// The generalizer on the paper's examples (docs/naturalization.md §6) with the real executor.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "equivalence.hpp"
#include "flipper/naturalization/generalizer.hpp"
#include "study_env.hpp"

using namespace flipper;
using naturalization::Generalizer;
using naturalization::GeneralizeResult;
using testsupport::P;

namespace {

// Stands in for the inducer's best-packing score: one point per head word the program contains
// as a subtree (the head chart's matches), like packing `3` in "drop 3 items".
std::function<double(const sdk::Program&)> packs(std::vector<sdk::Program> matches) {
  return [matches](const sdk::Program& program) {
    std::function<bool(const sdk::Program&, const sdk::Program&)> contains =
        [&](const sdk::Program& p, const sdk::Program& m) {
          if (sdk::equal(p, m)) return true;
          for (const auto& k : p->kids)
            if (contains(k, m)) return true;
          return false;
        };
    double score = 0;
    for (const auto& m : matches) score += contains(program, m) ? 1.0 : 0.0;
    return score;
  };
}

const naturalization::GeneralizeCandidate& find(const GeneralizeResult& r,
                                                const std::string& canonical) {
  for (const auto& c : r.candidates)
    if (sdk::equal(c.program, P(canonical))) return c;
  FAIL("no candidate " << canonical);
  throw std::logic_error("unreachable");
}

std::string winner(const GeneralizeResult& r) {
  return sdk::render(r.winner);
}

}  // namespace

TEST_CASE("generalize: drop 3 items := drop item x3 gives repeat 3 times drop item",
          "[generalize]") {
  testsupport::StudyEnv env;
  sdk::WorldState w = env.exec.run(P("{pick every item }"), env.at({7, 4})).world;
  Generalizer g(env.rewriter, nullptr, env.exec);
  const auto r =
      g.generalize(sdk::tokenize("drop 3 items"), P("{{drop item };{drop item };{drop item }}"), w,
                   packs({sdk::make_num(3)}));
  CHECK(winner(r) == sdk::render(P("{repeat 3 times {drop item }}")));
  CHECK_FALSE(r.body_won);
  CHECK(r.winner_rewriting == "loop");
  CHECK(r.candidates[0].rewriting == "body");
  CHECK(r.candidates[0].equivalent);
  CHECK(r.candidates[r.winner_index].packing_score == 1.0);
  // `drop every item` drops all four held items: discarded, with the step where it departs.
  const auto& every = find(r, "{drop every item }");
  CHECK_FALSE(every.equivalent);
  CHECK_THAT(every.rejected_reason, Catch::StartsWith("different trace at step 4"));
  // Without a packing reward, generality alone prefers the shortest equivalent program:
  // `drop item` x3 — is `repeat` (4 nodes) vs. body (7 nodes); `drop item` is not equivalent.
  const auto plain = g.generalize(sdk::tokenize("drop 3 items"),
                                  P("{{drop item };{drop item };{drop item }}"), w, {});
  CHECK(winner(plain) == sdk::render(P("{repeat 3 times {drop item }}")));
}

TEST_CASE("generalize: pick items is blue gives pick every item is blue", "[generalize]") {
  testsupport::StudyEnv env;
  // [3,8] holds a blue circle and a yellow square; add a blue square: exactly two blue items.
  sdk::WorldState w = env.at({3, 8});
  testsupport::StudyEnv::add_item(w, {3, 8}, "blue", "square");
  const auto body = P("{{pick item {is blue}};{pick item {is blue}}}");
  Generalizer g(env.rewriter, nullptr, env.exec);
  const auto blue = sdk::make_word(sdk::Kind::Color, "blue");
  const auto r = g.generalize(sdk::tokenize("pick items is blue"), body, w, packs({blue}));
  CHECK(winner(r) == sdk::render(P("{pick every item {is blue}}")));
  CHECK(r.winner_rewriting == "pick_by_predicate");
  // The body, the loop and `pick every item is blue` pack equally; generality decides.
  CHECK(find(r, "{repeat 2 times {pick item {is blue}}}").equivalent);
  CHECK(find(r, "{repeat 2 times {pick item {is blue}}}").packing_score == 1.0);
  CHECK(r.candidates[r.winner_index].packing_score == 1.0);
  // `pick every item` would be more general still, but it also picks the yellow square.
  const auto& every = find(r, "{pick every item }");
  CHECK_FALSE(every.equivalent);
  CHECK_FALSE(every.rejected_reason.empty());
  CHECK_FALSE(find(r, "{pick item {is blue}}").equivalent);
}

TEST_CASE("generalize: similarity decides before generality", "[generalize]") {
  testsupport::StudyEnv env;
  sdk::WorldState w = env.at({3, 8});
  testsupport::StudyEnv::add_item(w, {3, 8}, "blue", "square");
  // Vectors in which "items" reads like "repeat": the loop is now most similar to the head.
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "generalize_data";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "vectors.txt") << "items 1 0 0\nrepeat 1 0 0\nevery 0 1 0\npick 0 0 1\n";
  auto glove = testsupport::load_plugin<sdk::Similarity>(
      "glove", sdk::Params({{"path", (dir / "vectors.txt").string()}}));
  Generalizer g(env.rewriter, glove, env.exec);
  const auto blue = sdk::make_word(sdk::Kind::Color, "blue");
  const auto r = g.generalize(sdk::tokenize("pick items is blue"),
                              P("{{pick item {is blue}};{pick item {is blue}}}"), w, packs({blue}));
  CHECK(winner(r) == sdk::render(P("{repeat 2 times {pick item {is blue}}}")));
  CHECK(r.candidates[r.winner_index].similarity >
        find(r, "{pick every item {is blue}}").similarity);
  // Head words drop only punctuation; candidate words drop structure words.
  CHECK(naturalization::head_words(sdk::tokenize("pick items, [is] {blue}")) ==
        std::vector<std::string>{"pick", "items", "is", "blue"});
  CHECK(naturalization::candidate_words(
            P("{visit {world containing item {{is red} and {is triangle}}}}")) ==
        std::vector<std::string>{"visit", "world", "red", "triangle"});
}

TEST_CASE("generalize: visit red triangle := move right at [9,8]", "[generalize]") {
  testsupport::StudyEnv env;
  Generalizer g(env.rewriter, nullptr, env.exec);
  const auto red = sdk::make_word(sdk::Kind::Color, "red");
  const auto triangle = sdk::make_word(sdk::Kind::Shape, "triangle");
  const auto r = g.generalize(sdk::tokenize("visit red triangle"), P("{move right}"),
                              env.at({9, 8}), packs({red, triangle}));
  // The body and the seven candidates of §6 are equivalent, but the two with `green` narrow the
  // meaning with a colour neither the head nor the body mentions: discarded
  // (docs/naturalization.md).
  REQUIRE(r.candidates.size() == 8);
  for (const auto& c : r.candidates) {
    const std::string text = sdk::render(c.program);
    INFO(text << ": " << c.rejected_reason);
    if (text.find("green") != std::string::npos) {
      CHECK_FALSE(c.equivalent);
      CHECK(c.rejected_reason ==
            "narrows the meaning with 'green', which neither the head nor the body mentions");
    } else {
      CHECK(c.equivalent);
      CHECK(c.rejected_reason.empty());
    }
  }
  CHECK(winner(r) ==
        sdk::render(P("{visit {world containing item {{is red} and {is triangle}}}}")));
  CHECK(r.winner_rewriting == "visit_by_predicate");
  CHECK(find(r, "{visit [10,8]}").generality == -4);
}

namespace {
// A rewriter that proposes fixed programs, to show what the generalizer does with bad ones.
class FixedRewriter : public sdk::Rewriter {
 public:
  explicit FixedRewriter(std::vector<sdk::Program> programs) : programs_(std::move(programs)) {}

 protected:
  std::vector<sdk::RewriteCandidate> do_propose(const sdk::RewriteRequest&) const override {
    std::vector<sdk::RewriteCandidate> out;
    for (const auto& p : programs_) out.push_back({p, "fixed"});
    return out;
  }

 private:
  std::vector<sdk::Program> programs_;
};
}  // namespace

TEST_CASE("generalize: a non-equivalent candidate is never chosen", "[generalize]") {
  testsupport::StudyEnv env;
  const auto left = sdk::make_word(sdk::Kind::Direction, "left");
  FixedRewriter fixed({P("{move left}"), P("{{move right};{move right}}"), P("{visit room7}"),
                       sdk::make(sdk::Kind::VisitPoint, {sdk::make(sdk::Kind::PointVar)}),
                       P("{move left}"), P("{visit [10,8]}")});
  Generalizer g(kernel::PluginRef<const sdk::Rewriter>::borrowed(fixed), nullptr, env.exec);
  // Packing rewards `left`, which only the non-equivalent `move left` contains.
  const auto r =
      g.generalize(sdk::tokenize("go left"), P("{move right}"), env.at({9, 8}), packs({left}));
  REQUIRE(r.candidates.size() == 6);  // body + 5: the repeated `move left` is checked once
  CHECK_THAT(
      r.candidates[1].rejected_reason,
      Catch::Equals("different trace at step 1 (body: move to [10,8]; candidate: move to [8,8])"));
  CHECK_THAT(r.candidates[2].rejected_reason,
             Catch::Equals("different trace at step 2 (body: no step; candidate: move to [11,8])"));
  CHECK_THAT(r.candidates[3].rejected_reason, Catch::StartsWith("execution error: "));
  CHECK(r.candidates[4].rejected_reason == "not a complete statement");
  CHECK(r.candidates[5].equivalent);
  // Not `move left`, though it packs best: the body (2 nodes) beats `visit [10,8]` (4 nodes).
  CHECK(r.body_won);
  CHECK(winner(r) == sdk::render(P("{move right}")));
  for (const auto& c : r.candidates) CHECK(c.equivalent == c.rejected_reason.empty());
}

TEST_CASE("generalize: a body that errs keeps the body and rejects everything", "[generalize]") {
  testsupport::StudyEnv env;
  FixedRewriter fixed({P("{move left}")});
  const auto r =
      Generalizer(kernel::PluginRef<const sdk::Rewriter>::borrowed(fixed), nullptr, env.exec)
          .generalize({}, P("{{visit room7};{visit room7}}"), env.at({9, 8}), {});
  CHECK(r.body_won);
  CHECK(r.candidates[0].rejected_reason.empty());
  CHECK_FALSE(r.candidates[0].equivalent);
  REQUIRE(r.candidates[0].failed_checks.size() == 1);
  CHECK_THAT(r.candidates[0].failed_checks[0], Catch::StartsWith("execution error: "));
  CHECK_THAT(r.candidates[1].rejected_reason, Catch::StartsWith("execution error of the body: "));
  CHECK_FALSE(r.candidates[1].equivalent);
}

TEST_CASE("generalize: equivalence compares traces, then final worlds", "[generalize]") {
  testsupport::StudyEnv env;
  const sdk::Outcome a = env.exec.run(P("{move right}"), env.at({9, 8}));
  sdk::Outcome b = a;
  CHECK_FALSE(naturalization::generalize::difference(a, b).has_value());
  // Same trace, different final world (an executor defect would be needed for this; the check
  // is the safety net).
  b.world.robot = {4, 4};
  CHECK(naturalization::generalize::difference(a, b) ==
        std::optional<std::string>("different final world: robot at [10,8] vs [4,4]"));
  b = a;
  b.world.held.push_back({99, "red", "square"});
  CHECK(naturalization::generalize::difference(a, b) ==
        std::optional<std::string>("different final world: held items differ (0 vs 1)"));
  b = a;
  b.error = "boom";
  CHECK(naturalization::generalize::difference(a, b) ==
        std::optional<std::string>("execution error: boom"));
}
