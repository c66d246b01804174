// Seeing a definition generalise before it counts (docs/naturalization.md §5 "Preview",
// docs/protocol.md § define `preview`): the rules a definition would induce, for each a few new
// sentences it makes understandable with what they would do on the current world, and the
// perturbed check, with nothing stored; then the commit with some rules dropped. The expected
// sentences are hand-derived: the core grammar's phrases of a category are its first four words
// (colours black blue gray green, directions up down left right), the head's own skipped; the
// study map's robot starts at (2,4) with walls at (2,6) and (2,2).
#include <catch2/catch.hpp>

#include "naturalize_fixture.hpp"

using namespace flipper::naturalizetest;
using flipper::kernel::Json;

namespace {

Json preview_of(flipper::kernel::Session& s, const std::string& head,
                const std::vector<std::string>& body) {
  return ask(s, {{"op", "define"}, {"head", head}, {"body", body}, {"preview", true}});
}

// "text -> formula: moves, end, realizable" of each sentence of preview rule `i`.
std::vector<std::string> sentences(const Json& preview, std::size_t i) {
  std::vector<std::string> out;
  for (const auto& e : preview["preview"][i]["sentences"])
    out.push_back(e["text"].get<std::string>() + " -> " + e["formula"].get<std::string>() + ": " +
                  std::to_string(e["moves"].get<int>()) + " " + e["end"].dump() + " " +
                  (e["realizable"].get<bool>() ? "realizable" : "not realizable"));
  return out;
}

}  // namespace

TEST_CASE("a preview shows each rule's new sentences and what they do, storing nothing",
          "[naturalize][preview]") {
  auto s = open(scratch_path("preview") + ".sqlite");
  user(*s, "bob");
  const Json zap = preview_of(*s, "zap blue", {"pick item is blue"});
  INFO(zap.dump());
  REQUIRE(zap.value("ok", false));
  CHECK(zap["stored"] == false);
  REQUIRE(zap["preview"].size() == 3);
  CHECK(zap["preview"][0]["id"] == "new1");
  CHECK(zap["preview"][0]["rule"] == "$Action -> zap $Color");
  CHECK(zap["preview"][0]["semantics"] == "{pick item {is $1}}");
  CHECK(sentences(zap, 0) ==
        std::vector<std::string>{"zap black -> {pick item {is black}}: 0 null not realizable",
                                 "zap gray -> {pick item {is gray}}: 0 null not realizable",
                                 "zap green -> {pick item {is green}}: 0 null not realizable"});
  CHECK(zap["preview"][0]["sentences"][0]["warnings"] ==
        Json{"Could not complete the action: {pick item {is black}} (no black item here)"});
  CHECK(zap["preview"][1]["rule"] == "$Action -> zap $Property");
  CHECK(sentences(zap, 1) ==
        std::vector<std::string>{"zap triangle -> {pick item {is triangle}}: 0 null not realizable",
                                 "zap circle -> {pick item {is circle}}: 0 null not realizable",
                                 "zap square -> {pick item {is square}}: 0 null not realizable"});
  CHECK(zap["preview"][2]["rule"] == "$Action -> zap blue");
  CHECK(zap["preview"][2]["sentences"].empty());  // no hole: it reads only its head
  CHECK(zap["perturbed"] ==
        Json{{"checks", 0}, {"worlds", 0}, {"passed", 0}, {"failed", Json::array()}});
  CHECK(ask(*s, {{"op", "rules"}})["rules"].empty());

  const Json hop = preview_of(*s, "hop left twice", {"move left", "move left"});
  INFO(hop.dump());
  REQUIRE(hop["preview"].size() == 1);
  CHECK(hop["preview"][0]["rule"] == "$Action -> hop $Direction twice");
  CHECK(sentences(hop, 0) ==
        std::vector<std::string>{
            "hop up twice -> {{move up};{move up}}: 1 [2,5] not realizable",
            "hop down twice -> {{move down};{move down}}: 1 [2,3] not realizable",
            "hop right twice -> {{move right};{move right}}: 2 [4,4] realizable"});
  CHECK(hop["preview"][0]["sentences"][0]["warnings"] ==
        Json{"Could not complete the action: {move up} ([2,6] is a wall)"});
  // The other world: the first perturbed copy puts the robot at [11,7] (room5's corner): up
  // reaches [11,8] below the border, [11,6] below it and [12,7] right of it are walls.
  CHECK(hop["elsewhere"] == Json{{"robot", {11, 7}}, {"holding", 0}});
  std::vector<std::string> elsewhere;
  for (const auto& e : hop["preview"][0]["sentences"])
    elsewhere.push_back(std::to_string(e["elsewhere"]["moves"].get<int>()) + " " +
                        e["elsewhere"]["end"].dump() + " " +
                        (e["elsewhere"]["realizable"].get<bool>() ? "realizable" : "not"));
  CHECK(elsewhere == std::vector<std::string>{"1 [11,8] not", "0 null not", "0 null not"});
  CHECK(ask(*s, {{"op", "rules"}})["rules"].empty());
}

TEST_CASE("a definition is committed with the rules its author dropped left out",
          "[naturalize][preview]") {
  auto s = open(scratch_path("preview-drop") + ".sqlite");
  user(*s, "bob");
  const Json define_zap = {{"op", "define"}, {"head", "zap blue"}, {"body", {"pick item is blue"}}};
  auto with_drop = [&](const Json& drop) {
    Json r = define_zap;
    r["drop"] = drop;
    return ask(*s, r);
  };
  CHECK(error_code(with_drop({"new4"})) == "bad_request");  // three rules: new1..new3
  CHECK(error_code(with_drop({"new1", "new2", "new3"})) == "bad_request");
  CHECK(error_code(with_drop({3})) == "bad_request");
  CHECK(ask(*s, {{"op", "rules"}})["rules"].empty());
  const Json kept = with_drop({"new2", "new3"});
  INFO(kept.dump());
  REQUIRE(kept.value("ok", false));
  CHECK(kept["dropped"] == Json{"new2", "new3"});
  REQUIRE(kept["rules"].size() == 1);
  CHECK(kept["rules"][0]["rhs"] == Json{"zap", "$Color"});
  const Json rules = ask(*s, {{"op", "rules"}})["rules"];
  REQUIRE(rules.size() == 1);
  CHECK(rules[0]["rhs"] == Json{"zap", "$Color"});
  // `zap square` needed the dropped `zap $Property`; `zap red` reads with the kept rule.
  CHECK(status(*s, "zap square") != "induced");
  CHECK(status(*s, "zap red") == "induced");
}

TEST_CASE("a preview shows the perturbed check's result", "[naturalize][preview]") {
  auto s = open(scratch_path("preview-perturbed") + ".sqlite", {"induction.perturbed_checks=3"});
  user(*s, "bob");
  const Json hop = preview_of(*s, "hop left twice", {"move left", "move left"});
  INFO(hop.dump());
  // No rewriting beats the body, which agrees with itself on each of the 3 perturbed worlds.
  CHECK(hop["generalized"] == nullptr);
  CHECK(hop["perturbed"] ==
        Json{{"checks", 3}, {"worlds", 3}, {"passed", 3}, {"failed", Json::array()}});
}
