// Protocol framing and every error case: bad lines never end the session or lose state.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;
using flipper::testsupport::error_code;

namespace {

// Moves the robot so a lost state would show.
void move_robot(flipper::kernel::Session& s) {
  REQUIRE(ask(s, R"({"op":"query","text":"move up"})")["ok"] == true);
  REQUIRE(ask(s, R"({"op":"accept","rank":0})")["ok"] == true);
}

}  // namespace

TEST_CASE("blank lines get no answer", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  CHECK(s->handle_line("").empty());
  CHECK(s->handle_line("   \t\r").empty());
}

TEST_CASE("malformed lines are bad_json and keep the state", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  move_robot(*s);
  const Json before = ask(*s, R"({"op":"state"})")["world"];
  for (const char* line : {"not json", "{\"op\":\"state\"", "[1,2,3]", "42", "\"state\"", "null"}) {
    Json a = ask(*s, line);
    INFO(line);
    CHECK(a["ok"] == false);
    CHECK(error_code(a) == "bad_json");
    CHECK(a["error"]["message"].get<std::string>().size() > 10);
  }
  CHECK(ask(*s, R"({"op":"state"})")["world"] == before);
}

TEST_CASE("op and id are echoed, unknown ops and fields", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  Json a = ask(*s, R"({"op":"state","id":{"n":[1,"x"]},"extra":true})");
  CHECK(a["ok"] == true);
  CHECK(a["op"] == "state");
  CHECK(a["id"] == Json::parse(R"({"n":[1,"x"]})"));
  CHECK(a.contains("world"));

  a = ask(*s, R"({"op":"fly","id":7})");
  CHECK(a["ok"] == false);
  CHECK(a["op"] == "fly");
  CHECK(a["id"] == 7);
  CHECK(error_code(a) == "unknown_op");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("fly"));

  a = ask(*s, R"({"id":"x"})");
  CHECK(error_code(a) == "missing_field");
  CHECK(a["id"] == "x");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("'op'"));

  CHECK(error_code(ask(*s, R"({"op":3})")) == "bad_request");
  CHECK_FALSE(ask(*s, R"({"op":"state"})").contains("id"));
}

TEST_CASE("missing and mistyped fields name the field", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  struct Case {
    const char* line;
    const char* code;
    const char* field;
  };
  const Case cases[] = {
      {R"({"op":"query"})", "missing_field", "'text'"},
      {R"({"op":"query","text":null})", "missing_field", "'text'"},
      {R"({"op":"query","text":5})", "bad_request", "'text'"},
      {R"({"op":"query","text":"move up","k":"two"})", "bad_request", "'k'"},
      {R"({"op":"query","text":"move up","k":-1})", "bad_request", "'k'"},
      {R"({"op":"user"})", "missing_field", "'name'"},
      {R"({"op":"user","name":["a"]})", "bad_request", "'name'"},
      {R"({"op":"user","name":""})", "bad_request", "'name'"},
      {R"({"op":"accept"})", "missing_field", "'rank'"},
      {R"({"op":"accept","rank":"first"})", "bad_request", "'rank'"},
      {R"({"op":"accept","rank":0.5})", "bad_request", "'rank'"},
      {R"({"op":"world"})", "missing_field", "'file'"},
      {R"({"op":"world","world":[1]})", "bad_request", "'world'"},
      {R"({"op":"world","file":7})", "bad_request", "'file'"},
  };
  for (const auto& c : cases) {
    INFO(c.line);
    Json a = ask(*s, c.line);
    CHECK(a["ok"] == false);
    CHECK(error_code(a) == c.code);
    CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains(c.field));
  }
}

TEST_CASE("accept without a query, out of range, twice", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  CHECK(error_code(ask(*s, R"({"op":"accept","rank":0})")) == "no_query");
  Json q = ask(*s, R"({"op":"query","text":"move left","k":1})");
  REQUIRE(q["candidates"].size() == 1);
  for (const char* line : {R"({"op":"accept","rank":1})", R"({"op":"accept","rank":-1})"}) {
    Json a = ask(*s, line);
    CHECK(error_code(a) == "rank_out_of_range");
    CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("1 candidate"));
  }
  CHECK(ask(*s, R"({"op":"accept","rank":0})")["ok"] == true);
  // The query is consumed by the accept.
  CHECK(error_code(ask(*s, R"({"op":"accept","rank":0})")) == "no_query");
}

TEST_CASE("a candidate cut by a time limit refuses the whole query, naming the limit",
          "[session][protocol]") {
  // docs/planners.md §2: a time limit is never a different answer (here: a candidate shown as
  // erroneous beside the others); the query says deadline_exceeded, which limit fired in
  // `stopped`, and changes nothing.
  struct Limit {
    const char* set;
    const char* stopped;
    const char* message;
  };
  const Limit limits[] = {
      {"execution.cpu_budget_ms=1", "cpu_budget",
       "deadline exceeded while executing candidate 0: deadline exceeded: the execution used more "
       "CPU time than execution.cpu_budget_ms = 1 ms (stopped: cpu_budget)"},
      {"execution.deadline_ms=1", "wall_backstop",
       "deadline exceeded while executing candidate 0: deadline exceeded: the execution took "
       "longer than execution.deadline_ms = 1 ms, the wall-clock backstop (stopped: "
       "wall_backstop)"},
  };
  for (const Limit& limit : limits) {
    CAPTURE(limit.set);
    auto s = flipper::testsupport::bare_session({limit.set, "execution.step_budget=1000000000000",
                                                 "execution.action_budget=1000000000000"});
    move_robot(*s);
    const Json before = ask(*s, R"({"op":"state"})")["world"];
    Json q = ask(
        *s,
        R"({"op":"query","text":"repeat 99 times repeat 99 times repeat 99 times { move left ; move right }"})");
    CHECK(error_code(q) == "deadline_exceeded");
    CHECK(q["error"]["stopped"] == limit.stopped);
    CHECK(q["error"]["message"] == limit.message);
    CHECK(ask(*s, R"({"op":"state"})")["world"] == before);
    CHECK(error_code(ask(*s, R"({"op":"accept","rank":0})")) == "no_query");
  }
}

TEST_CASE("a define whose generalization meets the execution's CPU budget stores nothing",
          "[session][protocol]") {
  // A run cut by a time limit must not count as a program that errs (which would change which
  // rewriting wins with the machine's load): the define is refused whole.
  auto s = flipper::wiring::open_session(flipper::testsupport::test_runtime(
      {"execution.cpu_budget_ms=1", "execution.step_budget=1000000000000",
       "execution.action_budget=1000000000000"}));
  Json d = ask(
      *s,
      R"({"op":"define","head":"shuffle about","body":["repeat 99 times repeat 99 times repeat 99 times { move left ; move right }"]})");
  CHECK(error_code(d) == "deadline_exceeded");
  CHECK(d["error"]["stopped"] == "cpu_budget");
  CHECK_THAT(d["error"]["message"].get<std::string>(),
             Catch::StartsWith("deadline exceeded while generalizing the definition (deadline "
                               "exceeded: the execution used more CPU time than "
                               "execution.cpu_budget_ms = 1 ms (stopped: cpu_budget))"));
  CHECK(ask(*s, R"({"op":"rules"})")["rules"].empty());
}

TEST_CASE("an erroneous candidate is reported and cannot be accepted", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session({"execution.action_budget=50"});
  Json q = ask(*s, R"({"op":"query","text":"repeat 99 times repeat 99 times move left"})");
  REQUIRE(q["ok"] == true);
  REQUIRE(!q["candidates"].empty());
  const Json& c = q["candidates"][0];
  REQUIRE(c.contains("error"));
  CHECK(c["error"]["code"] == "budget_exceeded");
  CHECK(c["realizable"] == false);
  const Json before = ask(*s, R"({"op":"state"})")["world"];
  CHECK(c["world"] == before);
  Json a = ask(*s, R"({"op":"accept","rank":0})");
  CHECK(error_code(a) == "not_acceptable");
  CHECK(ask(*s, R"({"op":"state"})")["world"] == before);
}

TEST_CASE("input limits are input_too_long naming the limit", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session({"input.max_chars=40", "input.max_semicolons=3"});
  Json a = ask(*s, Json{{"op", "query"}, {"text", std::string(41, 'a')}}.dump());
  CHECK(error_code(a) == "input_too_long");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("input.max_chars = 40"));
  // The limit counts characters, not bytes: 40 two-byte letters pass it.
  std::string accents;
  for (int i = 0; i < 40; ++i) accents += "\xC3\xA9";
  CHECK(ask(*s, Json{{"op", "query"}, {"text", accents}}.dump())["ok"] == true);
  a = ask(*s, Json{{"op", "query"}, {"text", "move up ; move up ; move up ; move up"}}.dump());
  CHECK(error_code(a) == "input_too_long");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("input.max_semicolons = 3"));
  CHECK(ask(*s, Json{{"op", "query"}, {"text", "move up ; move up ; move up"}}.dump())["ok"] ==
        true);
}

TEST_CASE("a bare kernel session knows no naturalization op (the app layer wires them)",
          "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  for (const char* line : {R"({"op":"define","head":"x","body":["move up"]})", R"({"op":"rules"})",
                           R"({"op":"delete_rule","rule":"r1"})"}) {
    Json a = ask(*s, line);
    CHECK(a["ok"] == false);
    CHECK(error_code(a) == "unknown_op");
  }
}

TEST_CASE("a throwing plugin call is plugin_error and the session goes on", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  // The visibility filter runs inside the parser plugin's parse call.
  bool failing = true;
  s->install(flipper::kernel::make_extension([&failing](flipper::kernel::Session& session) {
    session.on<flipper::kernel::VisibilityAsked>([&failing](const auto& e) {
      if (failing)
        e.filter = [](const flipper::sdk::Rule&) -> bool {
          throw std::runtime_error("lexicon unavailable");
        };
    });
  }));
  Json a = ask(*s, R"({"op":"query","text":"move up"})");
  CHECK(a["ok"] == false);
  CHECK(error_code(a) == "plugin_error");
  CHECK_THAT(a["error"]["message"].get<std::string>(), Catch::Contains("lexicon unavailable"));
  failing = false;
  CHECK(ask(*s, R"({"op":"query","text":"move up"})")["ok"] == true);
}

TEST_CASE("the op table takes new ops and wraps existing ones", "[session][protocol]") {
  auto s = flipper::testsupport::bare_session();
  s->set_op("echo", [](flipper::kernel::Session&, const Json& r,
                       flipper::toolkit::json::JsonWriter& a) { a.key("text").value(r["text"]); });
  // The answer's bytes: ok, op, id first, then the handler's members in the order written.
  CHECK(s->handle_line(R"({"op":"echo","text":"hi","id":1})") ==
        R"({"ok":true,"op":"echo","id":1,"text":"hi"})");
  auto inner = *s->find_op("user");
  int calls = 0;
  s->set_op("user", [inner, &calls](flipper::kernel::Session& ss, const Json& r,
                                    flipper::toolkit::json::JsonWriter& a) {
    ++calls;
    inner(ss, r, a);
  });
  CHECK(ask(*s, R"({"op":"user","name":"ana"})")["name"] == "ana");
  CHECK(calls == 1);
  CHECK(s->user() == "ana");
}

TEST_CASE(
    "a world op's request tree keeps the world object empty and its world comes from the line",
    "[session][protocol]") {
  // handle_line keeps a top-level world object empty in the tree (its plugin reads the line's
  // text), so an op wrapping `world` still sees that a world object was sent; the last of two
  // "world" members decides, as in the tree.
  auto s = flipper::testsupport::bare_session();
  auto inner = *s->find_op("world");
  std::vector<std::string> seen;
  s->set_op("world", [inner, &seen](flipper::kernel::Session& ss, const Json& r,
                                    flipper::toolkit::json::JsonWriter& a) {
    seen.push_back(r.contains("world") ? r["world"].dump() : "absent");
    inner(ss, r, a);
  });
  const std::string world =
      R"({"bounds":{"max":[3,3],"min":[-1,-1]},"items":[{"color":"red","shape":"circle","x":1,)"
      R"("y":2}],"robot":{"x":0,"y":0,"items":[]},"walls":[[2,2]]})";
  Json a = ask(*s, R"({"op":"world","world":)" + world + R"(,"id":{"n":[1,{"m":2}]}})");
  REQUIRE(a["ok"] == true);
  CHECK(a["id"] == Json::parse(R"({"n":[1,{"m":2}]})"));  // other objects stay whole
  CHECK(a["world"]["items"] ==
        Json::parse(R"([{"color":"red","id":0,"shape":"circle","x":1,"y":2}])"));
  CHECK(a["world"]["walls"] == Json::parse("[[2,2]]"));
  CHECK(ask(*s, R"({"op":"world","world":{"x":1},"world":)" + world + "}")["ok"] == true);
  Json last_null = ask(*s, R"({"op":"world","world":)" + world + R"(,"world":null})");
  CHECK(error_code(last_null) == "missing_field");  // no world object, no file
  Json nested =
      ask(*s, R"({"op":"world","world":{"bounds":{"max":[1,1],"min":[0,0]},"a":{"b":}}})");
  CHECK(error_code(nested) == "bad_json");  // the left-out object's syntax is still checked
  CHECK(seen == std::vector<std::string>{"{}", "{}", "null"});
}
