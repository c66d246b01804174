// The optional equivalence checks on perturbed worlds: deterministic, reported per candidate, and
// ranking a candidate that differs there after ones that agree (when packing and similarity tie).
#include <catch2/catch.hpp>

#include "flipper/naturalization/generalizer.hpp"
#include "perturbation.hpp"
#include "study_env.hpp"

using namespace flipper;
using naturalization::Generalizer;
using testsupport::P;

namespace {
const naturalization::GeneralizeCandidate& find(const naturalization::GeneralizeResult& r,
                                                const std::string& text) {
  for (const auto& c : r.candidates)
    if (sdk::equal(c.program, P(text))) return c;
  FAIL("no candidate " << text);
  throw std::logic_error("unreachable");
}
}  // namespace

TEST_CASE("perturbations are deterministic and differ from the world", "[generalize][perturbed]") {
  testsupport::StudyEnv env;
  const auto a = naturalization::generalize::perturb(env.world, 12, 7);
  const auto b = naturalization::generalize::perturb(env.world, 12, 7);
  const auto c = naturalization::generalize::perturb(env.world, 12, 8);
  REQUIRE(a.size() == 12);
  bool any_seed_difference = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].same_state(b[i]));
    CHECK_FALSE(a[i].same_state(env.world));
    CHECK(a[i].geometry->is_free(a[i].robot));
    for (const auto& item : a[i].items) CHECK(a[i].geometry->is_free(item.at));
    CHECK(a[i].items.size() + a[i].held.size() == env.world.items.size());
    any_seed_difference = any_seed_difference || !a[i].same_state(c[i]);
  }
  CHECK(any_seed_difference);
}

TEST_CASE("perturbed checks rank robust candidates first on a tie", "[generalize][perturbed]") {
  testsupport::StudyEnv env;
  sdk::WorldState w = env.at({3, 8});
  testsupport::StudyEnv::add_item(w, {3, 8}, "blue", "square");
  const auto body = P("{{pick item {is blue}};{pick item {is blue}}}");
  Generalizer g(env.rewriter, nullptr, env.exec, {.perturbed_checks = 16});
  const auto r = g.generalize(sdk::tokenize("pick items is blue"), body, w, {});
  REQUIRE(r.perturbations == 16);
  const auto& loop = find(r, "{repeat 2 times {pick item {is blue}}}");
  const auto& every = find(r, "{pick every item {is blue}}");
  // The loop is the same program unrolled: equivalent on every world.
  CHECK(loop.perturbed_passed == 16);
  CHECK(loop.failed_checks.empty());
  // `pick every item is blue` differs when the robot's cell has another number of blue items.
  REQUIRE(every.equivalent);
  CHECK_FALSE(every.failed_checks.empty());
  CHECK(every.perturbed_passed + static_cast<int>(every.failed_checks.size()) == 16);
  CHECK_THAT(every.failed_checks[0], Catch::StartsWith("perturbation "));
  // Still eligible, but after the loop on this tie (without the checks it would win, see
  // test_generalizer.cpp).
  CHECK(sdk::render(r.winner) == sdk::render(P("{repeat 2 times {pick item {is blue}}}")));
  // Deterministic.
  const auto again = g.generalize(sdk::tokenize("pick items is blue"), body, w, {});
  CHECK(again.winner_index == r.winner_index);
  CHECK(find(again, "{pick every item {is blue}}").failed_checks == every.failed_checks);
}

TEST_CASE("perturbed checks do not override the packing score", "[generalize][perturbed]") {
  testsupport::StudyEnv env;
  Generalizer g(env.rewriter, nullptr, env.exec, {.perturbed_checks = 8});
  const auto packing = [&](const sdk::Program& p) {
    const std::string t = sdk::render(p);
    return (t.find("red") != std::string::npos ? 1.0 : 0.0) +
           (t.find("triangle") != std::string::npos ? 1.0 : 0.0);
  };
  const auto r =
      g.generalize(sdk::tokenize("visit red triangle"), P("{move right}"), env.at({9, 8}), packing);
  CHECK(sdk::render(r.winner) ==
        sdk::render(P("{visit {world containing item {{is red} and {is triangle}}}}")));
  CHECK_FALSE(r.candidates[r.winner_index].failed_checks.empty());
}
