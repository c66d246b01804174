// `flipper run` answers that repair (docs/usage.md "run", docs/protocol.md "Repairs"): a sentence
// nothing parsed gets the repl's repair lines, an unrealizable program the failing step, why and
// the nearest realizable variant; with --json the protocol's "repair" member. Expected texts are
// checked by hand against the study map (configs/default.yaml's world: robot at [2,4], red items
// at [4,0] in room2, [7,4] in room3 and [10,8] in room5, none at [2,4]).
#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"

using namespace flipper::clitest;
using nlohmann::json;

namespace {
const std::string kNoLexicon = " --set lexicon.path=:memory:";
}

TEST_CASE("run: not understood prints the repair's lines and its json", "[cli][run][repair]") {
  // 'xyzzy' is no word of the grammar; "move up" before it derives $ROOT; dropping the word
  // leaves the only nearest sentence, which is also the teach body (one understood phrase).
  const Run text = run_flipper("run 'move up xyzzy'" + kNoLexicon, false);
  CHECK(text.status == 1);
  CHECK(text.out == "");
  const Run both = run_flipper("run 'move up xyzzy'" + kNoLexicon);  // stderr only, as above
  CHECK(both.out.substr(both.out.find('\n') + 1) ==
        "Understood: \"move up\" = {move up}.\n"
        "Not understood: 'xyzzy' (unknown).\n"
        "Nearest sentences I understand:\n"
        "  1. move up   (drop 'xyzzy')\n"
        "Teach it in `flipper repl`: `:define`, then the steps: \"move up\".\n");
  // Two understood phrases around an unknown word: the teach body tiles them left to right.
  const Run two = run_flipper("run 'pick item is red then move left'" + kNoLexicon);
  CHECK(two.status == 1);
  CHECK(contains(two.out,
                 "Teach it in `flipper repl`: `:define`, then the steps: \"pick item is red\" "
                 "\"move left\".\n"));

  const Run j = run_flipper("run --json 'move up xyzzy'" + kNoLexicon, false);
  CHECK(j.status == 1);
  const json out = json::parse(j.out);
  CHECK(out["ok"] == false);
  CHECK(out["error"]["code"] == "bad_program");
  CHECK(out["repair"] == json::parse(R"({
    "understood": [{"start": 0, "end": 2, "text": "move up", "formula": "{move up}"}],
    "words": [{"at": 2, "word": "xyzzy", "kind": "unknown"}],
    "nearest": [{"text": "move up", "formula": "{move up}", "score": 4.0, "edits": 1,
                 "edit": "drop 'xyzzy'"}],
    "teach": {"op": "define", "head": "move up xyzzy", "body": ["move up"]}})"));
}

TEST_CASE("run: an unrealizable program says which step fails, why, and what works",
          "[cli][run][repair]") {
  // No item lies at [2,4]; the nearest realizable variant visits a red item first.
  const Run text = run_flipper("run 'pick item is red'" + kNoLexicon, false);
  CHECK(text.status == 0);
  CHECK(contains(text.out, "realizable: no\nrobot: [2,4], holding 0\n"));
  CHECK(text.out.substr(text.out.rfind("Cannot")) ==
        "Cannot be done here: {pick item {is red}} fails at [2,4]: no red item at [2,4], where "
        "the robot is; one lies in room2, room3, room5. Nearest that works: {{visit {world "
        "containing item {is red}}};{pick item {is red}}} (visit 'world containing item {is "
        "red}' first).\n");
  const json j = json::parse(run_flipper("run --json 'pick item is red'" + kNoLexicon, false).out);
  CHECK(j["realizable"] == false);
  CHECK(j["repair"] == json::parse(R"({"unrealizable": [{
    "rank": 0, "step": "{pick item {is red}}", "at": [2, 4],
    "why": "no red item at [2,4], where the robot is; one lies in room2, room3, room5",
    "variant": {"formula": "{{visit {world containing item {is red}}};{pick item {is red}}}",
                "edit": "visit 'world containing item {is red}' first", "edits": 1},
    "tried": 1}]})"));

  // A realizable program: no repair line, no member.
  const Run fine = run_flipper("run 'visit room1'" + kNoLexicon);
  CHECK(fine.status == 0);
  CHECK_FALSE(contains(fine.out, "Cannot be done here"));
  CHECK_FALSE(json::parse(run_flipper("run --json 'visit room1'" + kNoLexicon, false).out)
                  .contains("repair"));

  // An execution error the world decides (an unknown room): the error, then the repair.
  const Run room = run_flipper("run 'visit room9'" + kNoLexicon);
  CHECK(room.status == 1);
  CHECK(room.out ==
        "flipper run: [execution_error] unknown room 'room9' (this world defines room1, room2, "
        "room3, room4, room5)\n"
        "Cannot be done here: {visit room9} fails at [2,4]: unknown room 'room9' (this world "
        "defines room1, room2, room3, room4, room5). Nearest that works: {visit room1} (replace "
        "'room9' by 'room1').\n");
  const json e = json::parse(run_flipper("run --json 'visit room9'" + kNoLexicon, false).out);
  CHECK(e["error"]["code"] == "execution_error");
  CHECK(e["repair"]["unrealizable"][0]["variant"]["formula"] == "{visit room1}");
  CHECK(e["repair"]["unrealizable"][0]["step"] == "{visit room9}");
}
