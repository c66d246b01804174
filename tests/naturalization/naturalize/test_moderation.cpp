// Moderation of a shared lexicon (docs/naturalization.md §5 "Moderation"): under
// lexicon.moderation = hold_new a definition's rules are held, parse nobody's utterances (the
// author's included) until a researcher approves them; a rejected one leaves every parse as it
// was; holding, approving and rejecting are history entries naming who did it.
#include <catch2/catch.hpp>

#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/sdk/errors.hpp"
#include "naturalize_fixture.hpp"
#include "thrown_code.hpp"

using namespace flipper::naturalizetest;
using flipper::kernel::Json;
namespace nat = flipper::naturalization;

using flipper::testsupport::thrown_code;

namespace {

nat::Naturalizer& naturalizer_of(flipper::kernel::Session& s) {
  auto* ext = s.extension<nat::NaturalizationExtension>();
  REQUIRE(ext != nullptr);
  return *ext->naturalizer();
}

}  // namespace

TEST_CASE("a held definition changes no parse until approved and a rejected one never does",
          "[naturalize][moderation]") {
  const std::string store = scratch_path("moderation") + ".sqlite";
  auto bob = open(store, {"lexicon.moderation=hold_new"});
  user(*bob, "bob");
  auto ana = open(store, {"lexicon.moderation=hold_new"});
  user(*ana, "ana");
  const std::vector<std::string> phrases = {"zap red", "zap blue", "hop twice"};
  std::vector<std::string> before;
  for (const auto& p : phrases) before.push_back(first_formula(*ana, p));
  CHECK(before == std::vector<std::string>{"(none)", "(none)", "(none)"});

  const Json held = define(*bob, "zap blue", {"pick item is blue"});
  INFO(held.dump());
  REQUIRE(held.value("ok", false));
  CHECK(held["held"] == "h1");
  CHECK(held["stored"] == false);
  REQUIRE(held["rules"].size() == 3);  // zap $Color, zap $Property, zap blue
  CHECK(held["rules"][0]["id"] == "");
  const Json hop = define(*bob, "hop twice", {"move up", "move up"});
  REQUIRE(hop.value("ok", false));
  CHECK(hop["held"] == "h2");

  // Held: nobody's parses change, the author's included, and no rule is listed.
  for (std::size_t i = 0; i < phrases.size(); ++i) {
    CHECK(first_formula(*ana, phrases[i]) == before[i]);
    CHECK(first_formula(*bob, phrases[i]) == before[i]);
  }
  CHECK(ask(*ana, {{"op", "rules"}})["rules"].empty());
  nat::Naturalizer& moderator = naturalizer_of(*ana);
  const auto pending = moderator.pending();
  REQUIRE(pending.size() == 2);
  CHECK(pending[0].id == "h1");
  CHECK(pending[0].definition.author == "bob");
  CHECK(pending[0].definition.head == "zap blue");
  REQUIRE(pending[0].rules.size() == 3);
  CHECK(pending[0].rules[0].lhs == "$Action");
  CHECK(pending[1].id == "h2");

  // Rejected: gone from the queue, the parses are those of before.
  moderator.reject("rita", "h2", "duplicates move up");
  for (std::size_t i = 0; i < phrases.size(); ++i)
    CHECK(first_formula(*ana, phrases[i]) == before[i]);
  CHECK(thrown_code([&] { moderator.approve("rita", "h2"); }) == "not_found");
  CHECK(thrown_code([&] { moderator.reject("rita", "h9"); }) == "not_found");
  CHECK(thrown_code([&] { moderator.approve("rita", "x1"); }) == "not_found");

  // Approved (by another kernel over the same store): every user's parses see it.
  const auto approved = moderator.approve("rita", "h1");
  REQUIRE(approved.size() == 3);
  CHECK(approved[0]->id == "r1");
  CHECK(approved[0]->author == "bob");
  CHECK(first_formula(*ana, "zap red") == "{pick item {is red}}");
  CHECK(first_formula(*bob, "zap blue") == "{pick item {is blue}}");
  CHECK(first_formula(*ana, "hop twice") == "(none)");
  CHECK(ask(*bob, {{"op", "rules"}})["rules"].size() == 3);
  CHECK(moderator.pending().empty());

  // The history names each step and who took it.
  const auto history = moderator.store().history();
  std::vector<std::string> steps;
  for (const auto& e : history) steps.push_back(e.action + " " + e.author + " " + e.note);
  CHECK(steps == std::vector<std::string>{"hold bob h1", "hold bob h2",
                                          "reject rita h2: duplicates move up", "approve rita h1",
                                          "define bob ", "induce bob ", "induce bob ",
                                          "induce bob "});
  CHECK(history[3].head == "zap blue");
  CHECK(history[5].rule == "r1");
}

TEST_CASE("moderation off stores at once", "[naturalize][moderation]") {
  const std::string store = scratch_path("moderation-off") + ".sqlite";
  auto s = open(store);
  user(*s, "bob");
  const Json stored = define(*s, "hop twice", {"move up", "move up"});
  REQUIRE(stored.value("ok", false));
  CHECK_FALSE(stored.contains("held"));
  CHECK_FALSE(stored.contains("stored"));
  CHECK(naturalizer_of(*s).pending().empty());
  CHECK(first_formula(*s, "hop twice") == "{{move up};{move up}}");
}
