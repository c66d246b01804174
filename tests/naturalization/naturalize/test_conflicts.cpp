// Conflicts before they happen (docs/naturalization.md §5 "Conflicts", docs/protocol.md § define):
// a definition that would change another user's first reading, or give their phrase one more
// reading, says so before anything is stored (dry_run), says so when stored (warn), and is refused
// with nothing stored under lexicon.conflicts = refuse.
#include <catch2/catch.hpp>

#include "naturalize_fixture.hpp"

using namespace flipper::naturalizetest;
using flipper::kernel::Json;

namespace {

std::size_t rule_count(flipper::kernel::Session& s) {
  return ask(s, {{"op", "rules"}})["rules"].size();
}

}  // namespace

TEST_CASE("a definition that changes another user's first reading is shown, or refused",
          "[naturalize][conflicts]") {
  const std::string store = scratch_path("conflicts") + ".sqlite";
  auto bob = open(store);
  user(*bob, "bob");
  // bob's phrase: a constant rule (his body has no colour to match "red").
  REQUIRE(define(*bob, "zap red", {"move left"}).value("ok", false));
  const std::string bobs = first_formula(*bob, "zap red");
  REQUIRE(bobs == "{move left}");

  auto ana_refuse = open(store, {"lexicon.conflicts=refuse"});
  user(*ana_refuse, "ana");
  // "zap $Color" (simple packing of "blue") also reads "zap red", and ranks first: its colour
  // node is core (docs/naturalization.md §3, +1 per core node), bob's constant rule has none.
  const Json zap_blue = {{"op", "define"}, {"head", "zap blue"}, {"body", {"pick item is blue"}}};

  // Shown before it is stored: a dry run stores nothing, even under refuse.
  Json dry = zap_blue;
  dry["dry_run"] = true;
  const Json shown = ask(*ana_refuse, dry);
  INFO(shown.dump());
  REQUIRE(shown.value("ok", false));
  CHECK(shown["stored"] == false);
  REQUIRE(shown["conflicts"].size() == 1);
  const Json& c = shown["conflicts"][0];
  CHECK(c["phrase"] == "zap red");
  CHECK(c["user"] == "bob");
  CHECK(c["kind"] == "first_reading");
  CHECK(c["before"] == "{move left}");
  CHECK(c["after"] == "{pick item {is red}}");
  CHECK(c["readings_before"] == 1);
  CHECK(c["readings_after"] == 2);
  CHECK(shown["rules"].size() == 3);     // zap $Color, zap $Property, zap blue
  CHECK(shown["rules"][0]["id"] == "");  // not stored: no id
  CHECK(rule_count(*bob) == 1);
  CHECK(first_formula(*bob, "zap red") == bobs);

  // Refused under refuse: a clear code, nothing stored, bob reads as before.
  const Json refused = ask(*ana_refuse, zap_blue);
  INFO(refused.dump());
  CHECK(error_code(refused) == "definition_conflicts");
  CHECK(refused["error"]["message"].get<std::string>().find("'zap red' (bob)") !=
        std::string::npos);
  CHECK(rule_count(*bob) == 1);
  CHECK(first_formula(*bob, "zap red") == bobs);
  CHECK(first_formula(*ana_refuse, "zap blue") == "(none)");

  // A definition that reaches none of bob's phrases is stored under refuse, with no conflicts.
  const Json quiet = define(*ana_refuse, "zip blue", {"pick item is blue"});
  CHECK(quiet.value("ok", false));
  CHECK_FALSE(quiet.contains("conflicts"));
  CHECK_FALSE(quiet.contains("stored"));

  // Under warn (the default) it is stored, and the answer says what changed for bob.
  auto ana = open(store);
  user(*ana, "ana");
  const Json warned = ask(*ana, zap_blue);
  REQUIRE(warned.value("ok", false));
  REQUIRE(warned["conflicts"].size() == 1);
  CHECK(warned["conflicts"][0]["kind"] == "first_reading");
  CHECK(first_formula(*bob, "zap red") == "{pick item {is red}}");
}

TEST_CASE("a second reading of another user's phrase is a conflict, one's own phrases are not",
          "[naturalize][conflicts]") {
  const std::string store = scratch_path("conflicts-new") + ".sqlite";
  auto s = open(store);
  user(*s, "bob");
  REQUIRE(define(*s, "hop twice", {"move up", "move up"}).value("ok", false));
  // bob redefining his own phrase: no conflict with himself.
  const Json own = define(*s, "hop twice", {"move down", "move down"});
  REQUIRE(own.value("ok", false));
  CHECK_FALSE(own.contains("conflicts"));
  REQUIRE(define(*s, "zap blue", {"pick item is blue"}).value("ok", false));  // zap $Color, ...
  user(*s, "ana");
  // ana redefining bob's phrase: equal scores, the newer rule reads first (docs/naturalization.md
  // §2 "Order"), so bob's first reading changes.
  const Json other = define(*s, "hop twice", {"move left", "move left"});
  REQUIRE(other.value("ok", false));
  INFO(other.dump());
  REQUIRE(other["conflicts"].size() == 1);
  CHECK(other["conflicts"][0]["kind"] == "first_reading");
  CHECK(other["conflicts"][0]["before"] == "{{move down};{move down}}");
  CHECK(other["conflicts"][0]["after"] == "{{move left};{move left}}");
  CHECK(other["conflicts"][0]["readings_before"] == 2);
  CHECK(other["conflicts"][0]["readings_after"] == 3);
  // ana's constant rule for "zap blue" scores below bob's `zap $Color` (no core node): bob's
  // phrase keeps its first reading and gains one.
  const Json second = define(*s, "zap blue", {"move left"});
  REQUIRE(second.value("ok", false));
  INFO(second.dump());
  REQUIRE(second["conflicts"].size() == 1);
  CHECK(second["conflicts"][0]["phrase"] == "zap blue");
  CHECK(second["conflicts"][0]["kind"] == "new_reading");
  CHECK(second["conflicts"][0]["before"] == "{pick item {is blue}}");
  CHECK(second["conflicts"][0]["after"] == "{pick item {is blue}}");
  CHECK(second["conflicts"][0]["readings_before"] == 1);
  CHECK(second["conflicts"][0]["readings_after"] == 2);

  // Private lexicons: another user's rules never reach bob's parses.
  auto p = open(scratch_path("conflicts-private") + ".sqlite", {"lexicon.sharing=private"});
  user(*p, "bob");
  REQUIRE(define(*p, "zap red", {"move left"}).value("ok", false));
  user(*p, "ana");
  const Json priv = define(*p, "zap blue", {"pick item is blue"});
  REQUIRE(priv.value("ok", false));
  CHECK_FALSE(priv.contains("conflicts"));
}
