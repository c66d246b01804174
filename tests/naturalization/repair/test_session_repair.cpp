// Repairs of unparsable queries (docs/protocol.md § "Repairs"), through the protocol on the study
// map with the default grammar. Expected values are worked out by hand from the core grammar:
// "move up" and "move left" are commands ($ROOT), "xyzzy" and "vist" are no words of it.
#include <catch2/catch.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/wiring/session_factory.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;
using flipper::testsupport::error_code;

namespace {

// The session module's own ops and the repair extension (no lexicon wired in).
std::unique_ptr<flipper::kernel::Session> repair_session() {
  return std::make_unique<flipper::kernel::Session>(
      flipper::testsupport::test_runtime(),
      flipper::kernel::Session::Extensions{
          std::make_shared<flipper::naturalization::RepairExtension>()});
}

Json query(flipper::kernel::Session& s, const std::string& text, bool repair = true) {
  Json req{{"op", "query"}, {"text", text}};
  if (repair) req["repair"] = true;
  return ask(s, req.dump());
}

// The answer line without its timing field.
std::string masked(flipper::kernel::Session& s, const std::string& line) {
  Json a = Json::parse(s.handle_line(line));
  a["ms"] = 0;
  return a.dump();
}

// `n` words no grammar rule has, after "move up".
std::string noise(std::size_t n) {
  std::string text = "move up";
  for (std::size_t i = 0; i < n; ++i) text += " qq" + std::to_string(i);
  return text;
}

}  // namespace

TEST_CASE("a repair names the understood phrase, the unknown word and the nearest sentence",
          "[session][repair]") {
  auto s = repair_session();
  const Json a = query(*s, "move up xyzzy");
  REQUIRE(a["ok"] == true);
  CHECK(a["status"] == "unparsable");
  const Json& r = a["repair"];
  CHECK(r["understood"] ==
        Json::parse(R"([{"start":0,"end":2,"text":"move up","formula":"{move up}"}])"));
  CHECK(r["words"] == Json::parse(R"([{"at":2,"word":"xyzzy","kind":"unknown"}])"));
  REQUIRE(r["nearest"].size() == 1);
  CHECK(r["nearest"][0]["text"] == "move up");
  CHECK(r["nearest"][0]["formula"] == "{move up}");
  CHECK(r["nearest"][0]["edits"] == 1);
  CHECK(r["nearest"][0]["edit"] == "drop 'xyzzy'");
  CHECK(r["teach"] == Json::parse(R"({"op":"define","head":"move up xyzzy","body":["move up"]})"));
  CHECK_FALSE(r.contains("limited"));
}

TEST_CASE("a misspelt word is replaced by the closest known word", "[session][repair]") {
  auto s = repair_session();
  const Json r = query(*s, "vist room3")["repair"];
  CHECK(r["understood"] == Json::array());
  CHECK(r["words"] ==
        Json::parse(R"([{"at":0,"word":"vist","kind":"unknown","did_you_mean":"visit"},
                                      {"at":1,"word":"room3","kind":"misplaced"}])"));
  REQUIRE(r["nearest"].size() == 1);
  CHECK(r["nearest"][0]["text"] == "visit room3");
  CHECK(r["nearest"][0]["formula"] == "{visit room3}");
  CHECK(r["nearest"][0]["edit"] == "replace 'vist' by 'visit'");
}

TEST_CASE("two understood phrases side by side: a sequence, taught as two lines",
          "[session][repair]") {
  auto s = flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  const Json r = query(*s, "move up move left")["repair"];
  CHECK(r["understood"] ==
        Json::parse(R"([{"start":0,"end":2,"text":"move up","formula":"{move up}"},
                        {"start":2,"end":4,"text":"move left","formula":"{move left}"}])"));
  CHECK(r["words"] == Json::array());
  REQUIRE(r["nearest"].size() == 3);
  CHECK(r["nearest"][0]["text"] == "move up ; move left");
  CHECK(r["nearest"][0]["formula"] == "{{move up};{move left}}");
  CHECK(r["nearest"][1]["text"] == "move up");  // 2 words dropped; equal scores: earlier first
  CHECK(r["nearest"][2]["text"] == "move left");
  CHECK(r["teach"]["body"] == Json::parse(R"(["move up","move left"])"));
  // The suggestion is a define the session takes as it is.
  const Json d = ask(*s, r["teach"].dump());
  CHECK(d["ok"] == true);
  CHECK(query(*s, "move up move left")["status"] == "induced");
}

TEST_CASE("at most three nearest sentences: four understood phrases give the first three",
          "[session][repair]") {
  // docs/protocol.md, repair: `nearest` holds up to three sentences. Four phrases side by side
  // have four one-phrase readings (the whole sequence is more than two edits away).
  auto s = flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  const Json r = query(*s, "move up move left move down move right")["repair"];
  REQUIRE(r["understood"].size() == 4);
  REQUIRE(r["nearest"].size() == 3);
  CHECK(r["nearest"][0]["text"] == "move up");
  CHECK(r["nearest"][1]["text"] == "move left");
  CHECK(r["nearest"][2]["text"] == "move down");
}

TEST_CASE("words of the user's lexicon rules are known, so misplaced", "[session][repair]") {
  auto s = flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  REQUIRE(ask(*s, R"({"op":"define","head":"zig zag","body":["move up","move right"]})")["ok"] ==
          true);
  const Json r = query(*s, "zag zig")["repair"];
  CHECK(r["words"] == Json::parse(R"([{"at":0,"word":"zag","kind":"misplaced"},
                                      {"at":1,"word":"zig","kind":"misplaced"}])"));
  // Without the lexicon (the bare session) the same words are unknown.
  auto bare = repair_session();
  CHECK(query(*bare, "zag zig")["repair"]["words"][0]["kind"] == "unknown");
}

TEST_CASE("an edit in the middle: the misplaced word is dropped", "[session][repair]") {
  auto s = repair_session();
  const Json r = query(*s, "pick item is green and item is square")["repair"];
  REQUIRE(r["understood"].size() == 1);
  CHECK(r["understood"][0]["text"] == "pick item is green");
  CHECK(r["words"].size() == 4);
  CHECK(r["words"][0] == Json::parse(R"({"at":4,"word":"and","kind":"misplaced"})"));
  REQUIRE(r["nearest"].size() == 2);
  CHECK(r["nearest"][0]["text"] == "pick item is green and is square");
  CHECK(r["nearest"][0]["edit"] == "drop 'item'");
  CHECK(r["nearest"][1]["text"] == "pick item is green");
}

TEST_CASE("glued words are split, a trailing count repeats the phrase", "[session][repair]") {
  auto s = repair_session();
  const Json glued = query(*s, "pick itemis red")["repair"]["nearest"];
  REQUIRE(glued.size() == 2);
  CHECK(glued[0]["text"] == "pick item is red");
  CHECK(glued[0]["edit"] == "split 'itemis'");
  CHECK(glued[0]["formula"] == "{pick item {is red}}");
  // "3" alone could be dropped (1 edit) or make a repeat (2 edits); "3 times" only repeats.
  const Json count = query(*s, "move right 3")["repair"]["nearest"];
  REQUIRE(count.size() == 2);
  CHECK(count[0]["text"] == "move right");
  CHECK(count[1]["text"] == "repeat 3 times move right");
  CHECK(count[1]["edit"] == "repeat 'move right' 3 times");
  const Json times = query(*s, "move right 3 times")["repair"]["nearest"];
  REQUIRE(times.size() == 2);
  CHECK(times[0]["formula"] == "{repeat 3 times {move right}}");
}

TEST_CASE("a colour before 'item' is said as the core language says it", "[session][repair]") {
  auto s = repair_session();
  const Json r = query(*s, "drop red item")["repair"];
  REQUIRE(r["nearest"].size() >= 1);
  CHECK(r["nearest"][0]["text"] == "drop item is red");
  CHECK(r["nearest"][0]["formula"] == "{drop item {is red}}");
  CHECK(r["nearest"][0]["edit"] == "say 'red item' as 'item is red'");
}

TEST_CASE("answers with candidates, and queries without repair, are unchanged",
          "[session][repair]") {
  auto s = repair_session();
  CHECK(masked(*s, R"({"op":"query","text":"move up","repair":true})") ==
        masked(*s, R"({"op":"query","text":"move up"})"));
  CHECK(masked(*s, R"({"op":"query","text":"move up","repair":false})") ==
        masked(*s, R"({"op":"query","text":"move up"})"));
  const Json plain = query(*s, "move up xyzzy", false);
  CHECK(plain["status"] == "unparsable");
  CHECK_FALSE(plain.contains("repair"));
  CHECK_FALSE(query(*s, "move up")["ok"] == false);
  CHECK_FALSE(query(*s, "move up").contains("repair"));
  const Json bad = ask(*s, R"({"op":"query","text":"move up xyzzy","repair":1})");
  CHECK(error_code(bad) == "bad_request");
}

TEST_CASE("repair work is bounded by counts: tokens and edited sentences",
          "[session][repair][limits]") {
  using flipper::naturalization::kMaxRepairParses;
  using flipper::naturalization::kMaxRepairTokens;
  auto s = repair_session();
  // At the token limit the edited sentences are tried; one more token and they are not.
  const Json at = query(*s, noise(kMaxRepairTokens - 2))["repair"];
  REQUIRE(at["nearest"].size() == 1);
  CHECK(at["nearest"][0]["text"] == "move up");
  CHECK(at["limited"] == "only the first 48 edited sentences were tried");
  const Json over = query(*s, noise(kMaxRepairTokens - 1))["repair"];
  CHECK(over["nearest"] == Json::array());
  CHECK(over["limited"] ==
        "the utterance has 65 tokens; edited sentences are tried for 64 at most");
  CHECK(over["understood"].size() == 1);
  CHECK(over["words"].size() == kMaxRepairTokens - 1);

  // The typed service counts the parses: never more than kMaxRepairParses.
  flipper::kernel::QueryRequest req;
  req.text = noise(10);
  const auto few = flipper::naturalization::repair_query(*s, s->query(req));
  REQUIRE(few);
  // 10 drops, 9 joins, "drop every word", "keep only 'move up'", then pairs up to the bound.
  CHECK(few->parses == kMaxRepairParses);
  req.text = noise(1);
  const auto one = flipper::naturalization::repair_query(*s, s->query(req));
  REQUIRE(one);
  CHECK(one->parses == 2);  // "drop 'qq0'" (= "keep only 'move up'"), "join 'up qq0'"
  CHECK(one->limited.empty());
}
