// Rewritings 2-4 on the study map: which candidates the rewriter proposes, in which order.
#include <catch2/catch.hpp>

#include "flipper/testing/rewriter_conformance.hpp"
#include "study_env.hpp"

using namespace flipper;
using testsupport::P;

namespace {

std::vector<std::string> texts(const std::vector<sdk::RewriteCandidate>& cs) {
  std::vector<std::string> out;
  for (const auto& c : cs) out.push_back(c.rewriting + " " + sdk::render(c.program));
  return out;
}

std::string R(const std::string& rewriting, const std::string& canonical) {
  return rewriting + " " + sdk::render(P(canonical));
}

}  // namespace

TEST_CASE("rewrites: moves become a visit, then visits by predicate", "[rewrites]") {
  testsupport::StudyEnv env;
  // [9,8]: one step left of [10,8], where a green and a red triangle lie (in that order).
  const auto out = env.rewriter->propose({P("{move right}"), env.at({9, 8}), &env.exec, {}});
  const std::string v = "visit_by_predicate";
  CHECK(texts(out) == std::vector<std::string>{
                          R("moves_to_visit", "{visit [10,8]}"),
                          R(v, "{visit {world containing item }}"),
                          R(v, "{visit {world containing item {is green}}}"),
                          R(v, "{visit {world containing item {is triangle}}}"),
                          R(v, "{visit {world containing item {{is green} and {is triangle}}}}"),
                          R(v, "{visit {world containing item {is red}}}"),
                          R(v, "{visit {world containing item {{is red} and {is triangle}}}}"),
                      });
}

TEST_CASE("rewrites: a visit is rewritten by predicate but not into a point", "[rewrites]") {
  testsupport::StudyEnv env;
  const auto out = env.rewriter->propose({P("{visit [10,8]}"), env.at({9, 8}), &env.exec, {}});
  REQUIRE(out.size() == 6);
  for (const auto& c : out) CHECK(c.rewriting == "visit_by_predicate");
  // Moving onto an empty cell offers nothing to describe it by.
  CHECK(env.rewriter->propose({P("{move left}"), env.at({9, 8}), &env.exec, {}}).size() == 1);
}

TEST_CASE("rewrites: picks and drops by predicate of the items moved", "[rewrites]") {
  testsupport::StudyEnv env;
  // [7,4]: red circle, blue circle, green square, green circle.
  const auto out = env.rewriter->propose(
      {P("{{pick item {is red}};{pick item {is blue}}}"), env.at({7, 4}), &env.exec, {}});
  const std::string p = "pick_by_predicate";
  CHECK(texts(out) == std::vector<std::string>{
                          R(p, "{pick item }"),
                          R(p, "{pick every item }"),
                          R(p, "{pick item {is red}}"),
                          R(p, "{pick every item {is red}}"),
                          R(p, "{pick item {is circle}}"),
                          R(p, "{pick every item {is circle}}"),
                          R(p, "{pick item {{is red} and {is circle}}}"),
                          R(p, "{pick every item {{is red} and {is circle}}}"),
                          R(p, "{pick item {is blue}}"),
                          R(p, "{pick every item {is blue}}"),
                          R(p, "{pick item {{is blue} and {is circle}}}"),
                          R(p, "{pick every item {{is blue} and {is circle}}}"),
                      });
  // Drops: the robot holds what it picked.
  sdk::WorldState holding = env.exec.run(P("{pick every item }"), env.at({7, 4})).world;
  REQUIRE(holding.held.size() == 4);
  const auto drops = env.rewriter->propose(
      {P("{{drop item };{drop item };{drop item }}"), holding, &env.exec, {}});
  REQUIRE(drops.size() >= 3);
  CHECK(drops[0].rewriting == "loop");
  CHECK(sdk::render(drops[1].program) == sdk::render(P("{drop item }")));
  CHECK(drops[1].rewriting == "drop_by_predicate");
}

TEST_CASE("rewrites: mixed or failing bodies get no predicate rewritings", "[rewrites]") {
  testsupport::StudyEnv env;
  // Moves and picks: neither "only movement" nor "only picks".
  CHECK(env.rewriter->propose({P("{{move right};{pick item }}"), env.at({9, 8}), &env.exec, {}})
            .empty());
  // An execution error (unknown room): only loop rolling could apply.
  CHECK(env.rewriter->propose({P("{visit room7}"), env.at({9, 8}), &env.exec, {}}).empty());
  // max_candidates bounds the list.
  auto capped = testsupport::load_plugin<sdk::Rewriter>(
      "rewrites", sdk::Params({{"max_candidates", std::int64_t{3}}}));
  CHECK(capped->propose({P("{move right}"), env.at({9, 8}), &env.exec, {}}).size() == 3);
}

TEST_CASE("rewrites: rewriter conformance on the study map", "[rewrites][conformance]") {
  testsupport::StudyEnv env;
  testing::check_rewriter_conformance(*env.rewriter,
                                      {P("{move right}"), env.at({9, 8}), &env.exec, {"visit"}});
  testing::check_rewriter_conformance(
      *env.rewriter, {P("{{pick item };{pick item }}"), env.at({7, 4}), &env.exec, {}});
  testing::check_rewriter_conformance(
      *env.rewriter, {P("{{move up};{move up};{move left}}"), env.world, &env.exec, {}});
}
