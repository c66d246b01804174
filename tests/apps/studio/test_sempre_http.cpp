// GET /sempre as the 2018 web client uses it (docs/sempre.md): the exact request strings of the
// ten command forms, percent-encoded as encodeURIComponent encodes them, with the 2018 study map
// as context, and the answers' shapes checked field by field against hand-computed values.
#include "sempre_client.hpp"
#include "studio_server.hpp"

namespace flipper::sempretest {
namespace {

using studiotest::fresh_dir;
using studiotest::StudioServer;

const std::vector<std::string> kSempre = {"serve.sempre=true"};

json value_of(const json& candidate) {
  REQUIRE(candidate["value"].is_string());
  const json v = json::parse(candidate["value"].get<std::string>(), nullptr, false);
  REQUIRE(v.is_object());
  REQUIRE(v["status"].is_string());
  REQUIRE(v["path"].is_array());
  return v;
}

json step(int x, int y, const char* action, const char* color = "null", const char* shape = "null",
          bool possible = true) {
  return json::array({x, y, action, color, shape, possible});
}

// One query on the study map; the answer after its context.
json ask(httplib::Client& http, const std::string& sid, const std::string& text,
         const json& world) {
  const SempreReply c = sempre_get(http, context_command(world), sid);
  REQUIRE(c.status == 200);
  CHECK(c.body["lines"] == json::array());
  const SempreReply q = sempre_get(http, query_command(text), sid);
  REQUIRE(q.status == 200);
  return q.body;
}

}  // namespace

TEST_CASE("the client's encoding: the exact strings of the spec's forms") {
  // encodeURIComponent keeps ( ) ! * ' ~ - _ . and encodes spaces as %20.
  CHECK(encode_uri_component("(:q \"move left\")") == "(%3Aq%20%22move%20left%22)");
  CHECK(encode_uri_component("(:dictionary)") == "(%3Adictionary)");
  CHECK(encode_uri_component("(:delete 12)") == "(%3Adelete%2012)");
  CHECK(encode_uri_component("{2 + 1};é") == "%7B2%20%2B%201%7D%3B%C3%A9");
}

TEST_CASE("/sempre is off by default and answers 404 like any unknown path") {
  StudioServer server(fresh_dir("sempre-off"));
  auto http = server.client();
  auto res = http.Get(sempre_target("(:q \"move left\")", "abc").c_str());
  REQUIRE(res);
  CHECK(res->status == 404);
}

TEST_CASE(
    "transport: CORS for listed origins, JSON, pre-flights, ignored parameters, bad requests") {
  StudioServer server(fresh_dir("sempre-transport"),
                      {"serve.sempre=true", "serve.sempre_origins=[http://localhost:3000]"});
  auto http = server.client();
  // The literal target a browser sends for (:q "move left"), with the optional parameters.
  SempreReply r = sempre_get_target(
      http,
      "/sempre?format=lisp2json&q=(%3Aq%20%22move%20left%22)&sessionId=k3j9x0a1bz&logging=0"
      "&cite=0&grammar=0&learn=0&stats=0");
  CHECK(r.status == 200);
  CHECK(r.allow_origin.empty());  // no browser: no CORS header needed
  CHECK(r.content_type.rfind("application/json", 0) == 0);
  CHECK(r.body["candidates"][0]["formula"] == "{move left}");
  // '+' is a space (form decoding, as the original), %2B a plus.
  r = sempre_get_target(http, "/sempre?format=lisp2json&q=(%3Aq+%22move+left%22)&sessionId=k3");
  CHECK(r.body["candidates"][0]["formula"] == "{move left}");
  // Text that does not start with "(:" is a query.
  CHECK(sempre_get(http, "move right", "k3").body["candidates"][0]["formula"] == "{move right}");
  // A pre-flight from a listed origin is answered with the CORS headers (that origin) and no body.
  httplib::Headers preflight{{"Origin", "http://localhost:3000"},
                             {"Access-Control-Request-Method", "GET"}};
  auto res = http.Options("/sempre", preflight);
  REQUIRE(res);
  CHECK(res->status == 204);
  CHECK(res->get_header_value("Access-Control-Allow-Origin") == "http://localhost:3000");
  CHECK(res->get_header_value("Access-Control-Allow-Methods").find("GET") != std::string::npos);
  // A request from the listed origin is answered (that is the point), with the same header.
  res = http.Get(sempre_target("(:dictionary)", "k3").c_str(),
                 httplib::Headers{{"Origin", "http://localhost:3000"}});
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Access-Control-Allow-Origin") == "http://localhost:3000");
  // The server's own page (same origin) is answered too.
  res = http.Get(sempre_target("(:dictionary)", "k3").c_str(),
                 httplib::Headers{{"Origin", server.origin()}, {"Sec-Fetch-Site", "same-origin"}});
  REQUIRE(res);
  CHECK(res->status == 200);
  // Missing parameters, bad escapes, bad sessionIds and unknown commands: 400, a line saying
  // why, and still the answer's shape (a client reading `candidates` does not break).
  for (const std::string& target :
       {std::string("/sempre?format=lisp2json&sessionId=k3"),
        std::string("/sempre?format=lisp2json&q=(%3Adictionary)"),
        std::string("/sempre?q=%ZZ&sessionId=k3"),
        std::string("/sempre?q=(%3Adictionary)&sessionId=a%20b"),
        "/sempre?q=(%3Adictionary)&sessionId=" + std::string(129, 'x'),
        sempre_target("(:frobnicate)", "k3"), sempre_target("(:q move)", "k3"),
        sempre_target("(:delete twelve)", "k3"), sempre_target("(:accept \"x\")", "k3")}) {
    INFO(target);
    r = sempre_get_target(http, target);
    CHECK(r.status == 400);
    CHECK(r.allow_origin.empty());  // a program: no CORS header
    REQUIRE(r.body["lines"].size() == 1);
    CHECK(r.body["candidates"] == json::array());
    CHECK(r.body["error"]["code"].is_string());
  }
  // 128 characters are a valid sessionId.
  CHECK(sempre_get(http, "(:dictionary)", std::string(128, 'x')).status == 200);
}

TEST_CASE(":q answers stats, lines and candidates of the spec's shape on the 2018 map") {
  StudioServer server(fresh_dir("sempre-query"), kSempre);
  auto http = server.client();
  const json map = study_map();

  json a = ask(http, "s1", "move left", map);
  CHECK(a["stats"]["type"] == "q");
  CHECK(a["stats"]["size"] == 1);
  CHECK(a["stats"]["status"] == "Core");
  CHECK(a["stats"]["author"].is_null());
  CHECK(a["stats"]["walltime"].is_number());
  CHECK(a["stats"]["count"].is_number_unsigned());
  CHECK(a["lines"] == json::array());
  REQUIRE(a["candidates"].size() == 1);
  const json& c = a["candidates"][0];
  CHECK(c["formula"] == "{move left}");
  CHECK(c["prettyString"] == "{move left}");
  CHECK(c["score"].is_number());
  CHECK(c["prob"] == 1.0);
  CHECK(c["anchored"] == true);
  // The original's answer for this query (original-answers.jsonl): the same path.
  CHECK(value_of(c) ==
        json{{"status", ""}, {"path", {step(2, 4, "path"), step(1, 4, "destination")}}});

  // core-language §10 example 2: five steps east to (7,4), then the first red item there.
  a = ask(http, "s1", "visit world containing item is red; pick item is red", map);
  CHECK(value_of(a["candidates"][0]) ==
        json{{"status", ""},
             {"path",
              {step(2, 4, "path"), step(3, 4, "path"), step(4, 4, "path"), step(5, 4, "path"),
               step(6, 4, "path"), step(7, 4, "destination"),
               step(7, 4, "pickitem", "red", "circle")}}});

  // A failed pick: its entry with possible = false at the robot's cell, the warning as status.
  a = ask(http, "s1", "pick item", map);
  json v = value_of(a["candidates"][0]);
  CHECK(v["path"] == json::array({step(2, 4, "pickitem", "null", "null", false)}));
  CHECK(v["status"].get<std::string>().rfind("Could not complete the action: {pick item }", 0) ==
        0);

  // §10 example 3: the second step hits the wall at (2,6); the robot stays at (2,5).
  a = ask(http, "s1", "move up; move up", map);
  v = value_of(a["candidates"][0]);
  CHECK(v["path"] == json::array({step(2, 4, "path"), step(2, 5, "destination")}));
  CHECK(v["status"].get<std::string>().rfind("Could not complete the action: {move up}", 0) == 0);

  // Each move of a loop is a movement of its own (as the original printed it).
  a = ask(http, "s1", "repeat 3 times move right", map);
  CHECK(value_of(a["candidates"][0])["path"] ==
        json::array({step(2, 4, "path"), step(3, 4, "destination"), step(4, 4, "destination"),
                     step(5, 4, "destination")}));

  // Visiting the robot's own cell: one destination; a later movement has no start entry.
  a = ask(http, "s1", "visit [2,4]; move right", map);
  CHECK(value_of(a["candidates"][0])["path"] ==
        json::array({step(2, 4, "destination"), step(3, 4, "destination")}));

  // Two readings, both answered with numeric scores; probabilities sum to 1.
  a = ask(http, "s1", "visit room3 or room5 containing item is red", map);
  REQUIRE(a["candidates"].size() == 2);
  CHECK(a["stats"]["size"] == 2);
  CHECK(a["candidates"][0]["formula"] != a["candidates"][1]["formula"]);
  CHECK(a["candidates"][0]["prob"].get<double>() + a["candidates"][1]["prob"].get<double>() ==
        Approx(1.0));

  // Not understood: no candidates (the client then offers a definition).
  a = ask(http, "s1", "zorp the blorp", map);
  CHECK(a["stats"]["status"] == "Nothing");
  CHECK(a["stats"]["size"] == 0);
  CHECK(a["candidates"] == json::array());
  CHECK(a["lines"] == json::array());

  // The robot and what it carries come from the context: carrying a red triangle at (9,0).
  json moved = map;
  moved["robot"] = {{"x", 9}, {"y", 0}, {"holding", {{{"color", "red"}, {"shape", "triangle"}}}}};
  a = ask(http, "s1", "drop item; move left", moved);
  CHECK(value_of(a["candidates"][0])["path"] ==
        json::array({step(9, 0, "dropitem", "red", "triangle"), step(9, 0, "path"),
                     step(8, 0, "destination")}));
}

// Each 'or'/'containing' doubles the readings of a chain.
const std::string kChain =
    "visit room1 or room2 containing item or room3 containing item or room4 containing item or "
    "room5 containing item or room6 containing item";

TEST_CASE("more than 50 readings: the first 50 and the line 'Exceeded max options'") {
  // The chart parser keeps 50 derivations per cell by default: a wider beam finds more.
  StudioServer server(fresh_dir("sempre-many"), {"serve.sempre=true", "parser.params.beam=200"});
  auto http = server.client();
  const json a = ask(http, "s1", kChain, study_map());
  REQUIRE(a["candidates"].size() == 50);
  CHECK(a["stats"]["size"] == 50);
  CHECK(a["lines"] == json::array({"Exceeded max options"}));
  // With the default beam the same query has exactly 50 readings: all answered, no line.
  StudioServer fifty(fresh_dir("sempre-fifty"), kSempre);
  auto http50 = fifty.client();
  const json b = ask(http50, "s1", kChain, study_map());
  CHECK(b["candidates"].size() == 50);
  CHECK(b["lines"] == json::array());
}

TEST_CASE("a context that is not a world is refused with a line, and the next query says so") {
  StudioServer server(fresh_dir("sempre-context"), kSempre);
  auto http = server.client();
  for (const std::string& bad :
       {std::string("not json"), std::string("{\"robot\":[0,0,[]],\"world\":[]}"),
        std::string("{\"robot\":[0,0],\"world\":[],\"rooms\":{}}"),
        std::string("{\"robot\":[0,0,[]],\"world\":[[1,1,\"lava\",null,null]],\"rooms\":{}}"),
        std::string("{\"robot\":[0.5,0,[]],\"world\":[],\"rooms\":{}}"),
        std::string("{\"robot\":[1,1,[]],\"world\":[[1,1,\"wall\",null,null]],\"rooms\":{}}")}) {
    INFO(bad);
    const SempreReply r = sempre_get(http, "(:context " + json(bad).dump() + ")", "s2");
    CHECK(r.status == 200);
    REQUIRE(r.body["lines"].size() == 1);
    CHECK(r.body["error"]["code"] == "bad_world");
  }
  const SempreReply q = sempre_get(http, query_command("move left"), "s2");
  REQUIRE(q.body["lines"].size() == 1);
  CHECK(q.body["lines"][0].get<std::string>().find("refused") != std::string::npos);
  // A good context clears it.
  ask(http, "s2", "move left", study_map());
  CHECK(sempre_get(http, query_command("move left"), "s2").body["lines"] == json::array());
}

TEST_CASE(":accept learns from the reading its formula names, whatever came between") {
  StudioServer server(fresh_dir("sempre-accept"), kSempre);
  auto http = server.client();
  const json map = study_map();
  const std::string text = "visit room3 or room5 containing item is red";
  auto scores = [&] {
    std::map<std::string, double> out;
    const json a = ask(http, "s3", text, map);
    for (const auto& c : a["candidates"]) out[c["formula"]] = c["score"];
    return out;
  };
  const auto before = scores();
  REQUIRE(before.size() == 2);
  // The reading ranked second now; accepting it must raise it against the first.
  const json first = ask(http, "s3", text, map)["candidates"][0];
  const json second = ask(http, "s3", text, map)["candidates"][1];
  const std::string second_formula = second["formula"];
  const double gap_before = before.at(second_formula) - before.at(first["formula"]);
  // The accept arrives after the client's next context and query (it does not wait for it).
  ask(http, "s3", "move left", map);
  SempreReply r = sempre_get(
      http, "(:accept " + json(text).dump() + " " + json(second_formula).dump() + ")", "s3");
  CHECK(r.status == 200);
  CHECK(r.body["lines"] == json::array());
  CHECK(r.body["stats"]["type"] == "accept");
  const auto after = scores();
  CHECK(after.at(second_formula) - after.at(first["formula"]) > gap_before);
  // The accept did not move the session's world: the next query still starts at (2,4).
  CHECK(value_of(ask(http, "s3", "move left", map)["candidates"][0])["path"][0] ==
        step(2, 4, "path"));
  // The original's notation names a reading too; an unknown reading is refused with a line.
  r = sempre_get(http, "(:accept \"move left\" \"(: move left)\")", "s3");
  CHECK(r.body["lines"] == json::array());
  r = sempre_get(http, "(:accept \"move left\" \"{move right}\")", "s3");
  REQUIRE(r.body["lines"].size() == 1);
  CHECK(r.body["error"]["code"] == "not_acceptable");
  r = sempre_get(http, "(:accept \"move left\" \"(: fly left)\")", "s3");
  CHECK(r.body["error"]["code"] == "bad_program");
}

TEST_CASE(":reject in every logged spacing answers nothing to show") {
  StudioServer server(fresh_dir("sempre-reject"), kSempre);
  auto http = server.client();
  for (const std::string& command :
       {std::string("(:reject \"move left\" )"), std::string("(:reject \"move left\")"),
        std::string("(:reject \"move left\"   )"),
        std::string("(:reject \"pick item\" \"(: itemActionHandler pick (call setLimit (number 1) "
                    "(call allItems)))\")"),
        std::string("(:reject \"a\" \"f1\" \"f2\" \"f3\")")}) {
    INFO(command);
    const SempreReply r = sempre_get(http, command, "s4");
    CHECK(r.status == 200);
    CHECK(r.body["stats"]["type"] == "reject");
    CHECK(r.body["lines"] == json::array());
    CHECK(r.body["candidates"] == json::array());
  }
}

TEST_CASE(":def, :def_ret, :def_iso induce from the accepted formulas, :dictionary, :delete") {
  StudioServer server(fresh_dir("sempre-define"), kSempre);
  auto http = server.client();
  const json map = study_map();
  // Two steps of history, as the client sends them: a JSON string holding JSON text.
  const std::string body = json::array({json::array({"move up", "{move up}"}),
                                        json::array({"move right", "(: move right)"})})
                               .dump();
  SempreReply r = sempre_get(http, "(:def \"zig zag\" " + json(body).dump() + ")", "ana1");
  CHECK(r.status == 200);
  CHECK(r.body["stats"]["type"] == "def");
  CHECK(r.body["lines"] == json::array());
  REQUIRE(r.body["candidates"].size() == 1);
  CHECK(r.body["candidates"][0]["formula"] == "{{move up};{move right}}");
  // The head as typed (quotes unescaped, a trailing space) and a one-step body: :def_ret.
  r = sempre_get(http,
                 "(:def_ret \"hop \"twice\" \" " +
                     json(json::array({json::array({"repeat 2 times move up",
                                                    "(:loop (number 2) (: move up))"})})
                              .dump())
                         .dump() +
                     ")",
                 "ana1");
  CHECK(r.body["lines"] == json::array());
  CHECK(r.body["candidates"][0]["formula"] == "{repeat 2 times {move up}}");
  // A whole history: :def_iso; a step that was itself a definition carries that formula.
  r = sempre_get(http,
                 "(:def_iso \"zig zag hop\" " +
                     json(json::array({json::array({"zig zag", "{{move up};{move right}}"}),
                                       json::array({"move left", "{move left}"})})
                              .dump())
                         .dump() +
                     ")",
                 "bob2");
  CHECK(r.body["lines"] == json::array());
  CHECK(r.body["candidates"][0]["formula"] == "{{move up};{move right};{move left}}");

  // The definitions are understood, with their author's sessionId.
  json a = ask(http, "bob2", "zig zag", map);
  CHECK(a["stats"]["status"] == "Induced");
  CHECK(a["stats"]["author"] == "ana1");
  CHECK(a["candidates"][0]["formula"] == "{{move up};{move right}}");
  CHECK(value_of(a["candidates"][0])["path"] ==
        json::array({step(2, 4, "path"), step(2, 5, "destination"), step(3, 5, "destination")}));

  // Failures: a line saying why, no candidate (the client stays in define mode).
  for (const std::string& bad :
       {"(:def \"move up\" " +
            json(json::array({json::array({"move up", "{move up}"})}).dump()).dump() + ")",
        "(:def \"fly\" " + json(json::array().dump()).dump() + ")",
        "(:def \"fly\" " + json("not a list").dump() + ")",
        "(:def \"fly\" " + json(json::array({json::array({"zorp", "()"})}).dump()).dump() + ")",
        "(:def \"fly\" " + json(json::array({json::array({"up", "(: fly)"})}).dump()).dump() +
            ")"}) {
    INFO(bad);
    r = sempre_get(http, bad, "ana1");
    CHECK(r.status == 200);
    REQUIRE(r.body["lines"].size() == 1);
    CHECK(r.body["candidates"] == json::array());
  }

  // The dictionary: a JSON string of {index, rhs, head, body, uid}, every rule when shared.
  r = sempre_get(http, "(:dictionary)", "carl3");
  CHECK(r.body["stats"]["type"] == "dictionary");
  REQUIRE(r.body["stats"]["dictionary"].is_string());
  json dict = json::parse(r.body["stats"]["dictionary"].get<std::string>());
  REQUIRE(dict.is_array());
  REQUIRE(dict.size() >= 3);
  std::map<std::string, json> by_head;
  for (const auto& e : dict) {
    CHECK(e["index"].is_number_integer());
    CHECK(e["rhs"].is_string());
    CHECK(e["body"].is_string());
    by_head[e["head"]] = e;
  }
  REQUIRE(by_head.count("zig zag"));
  CHECK(by_head["zig zag"]["uid"] == "ana1");
  CHECK(by_head["zig zag"]["rhs"] == "zig zag");
  CHECK(by_head["zig zag"]["body"] == "move up; move right");
  REQUIRE(by_head.count("hop \"twice\" "));
  CHECK(by_head["zig zag hop"]["uid"] == "bob2");

  // Deletion: only the author; indexes stay what they were.
  const auto index_of = [&](const std::string& head) { return by_head[head]["index"].get<long>(); };
  r = sempre_get(http, "(:delete " + std::to_string(index_of("zig zag")) + ")", "bob2");
  REQUIRE(r.body["lines"].size() == 1);
  CHECK(r.body["error"]["code"] == "forbidden");
  r = sempre_get(http, "(:delete " + std::to_string(index_of("zig zag")) + ")", "ana1");
  CHECK(r.body["lines"] == json::array());
  r = sempre_get(http, "(:delete 999999)", "ana1");
  CHECK(r.body["error"]["code"] == "not_found");
  dict = json::parse(
      sempre_get(http, "(:dictionary)", "ana1").body["stats"]["dictionary"].get<std::string>());
  for (const auto& e : dict) {
    CHECK(e["head"] != "zig zag");
    CHECK(e["index"] == by_head[e["head"]]["index"]);  // the others kept their index
  }
  CHECK(dict.size() == by_head.size() - 1);
}

TEST_CASE("private lexicon: a sessionId sees and uses only its own rules") {
  StudioServer server(fresh_dir("sempre-private"),
                      {"serve.sempre=true", "lexicon.sharing=private"});
  auto http = server.client();
  const std::string body = json::array({json::array({"move up", "{move up}"})}).dump();
  REQUIRE(
      sempre_get(http, "(:def_ret \"go north\" " + json(body).dump() + ")", "p1").body["lines"] ==
      json::array());
  CHECK(ask(http, "p1", "go north", study_map())["stats"]["status"] == "Induced");
  CHECK(ask(http, "p2", "go north", study_map())["stats"]["status"] == "Nothing");
  const auto dict = [&](const std::string& sid) {
    return json::parse(
        sempre_get(http, "(:dictionary)", sid).body["stats"]["dictionary"].get<std::string>());
  };
  CHECK(dict("p1").size() == 1);
  CHECK(dict("p2") == json::array());
}

TEST_CASE("sessionIds are names of their own: no /api/v1 session can take or act as one") {
  StudioServer server(fresh_dir("sempre-names"), kSempre);
  auto http = server.client();
  const std::string body = json::array({json::array({"move up", "{move up}"})}).dump();
  REQUIRE(
      sempre_get(http, "(:def_ret \"go north\" " + json(body).dump() + ")", "ana").body["lines"] ==
      json::array());
  // The rule's author is sempre:ana; no account can be named so (docs/accounts.md: names are
  // letters, digits, '.', '_', '-') ...
  CHECK(server.run_accounts("add sempre:ana", "a long enough password\n").status == 2);
  // ... a guest session cannot become that user ...
  const std::string guest = studiotest::new_session(http);
  studiotest::Reply r = studiotest::post(http, guest, R"({"op":"user","name":"sempre:ana"})");
  CHECK(r.body["error"]["code"] == "forbidden");
  // ... and the account "ana" is another user, who may not delete sempre:ana's rule.
  server.add_account("ana", "a long enough password");
  const std::string cookie =
      studiotest::login(http, json{{"name", "ana"}, {"password", "a long enough password"}});
  REQUIRE_FALSE(cookie.empty());
  const std::string session = studiotest::new_session(http, studiotest::cookie(cookie));
  r = studiotest::post(http, session, R"({"op":"rules"})", studiotest::cookie(cookie));
  REQUIRE(r.body["rules"].size() == 1);
  CHECK(r.user == "ana");
  CHECK(r.body["rules"][0]["author"] == "sempre:ana");
  r = studiotest::post(http, session,
                       json{{"op", "delete_rule"}, {"rule", r.body["rules"][0]["id"]}}.dump(),
                       studiotest::cookie(cookie));
  CHECK(r.body["error"]["code"] == "forbidden");
}

TEST_CASE("/sempre sessions are bounded by serve.max_sessions") {
  StudioServer server(fresh_dir("sempre-bounded"), {"serve.sempre=true", "serve.max_sessions=2"});
  auto http = server.client();
  CHECK(sempre_get(http, "(:dictionary)", "a").status == 200);
  CHECK(sempre_get(http, "(:dictionary)", "b").status == 200);
  const SempreReply r = sempre_get(http, "(:dictionary)", "c");
  CHECK(r.status == 503);
  CHECK(r.body["error"]["code"] == "too_many_sessions");
  CHECK(sempre_get(http, "(:dictionary)", "a").status == 200);  // known ones go on
}

TEST_CASE("/sempre refuses other origins before running anything, and '*' opens it to all") {
  StudioServer server(fresh_dir("sempre-origins"), kSempre);
  auto http = server.client();
  http.set_url_encode(false);  // the targets are encoded already
  const std::string steps = json::array({json::array({"move up", "{move up}"})}).dump();
  const std::string def = sempre_target("(:def \"hop\" " + json(steps).dump() + ")", "eve");
  // A page of another origin (fetch sends Origin), or one that sends no Origin but is marked
  // cross-site by the browser (an <img> or a link): 403, and the definition is not stored.
  for (const httplib::Headers& h :
       {httplib::Headers{{"Origin", "http://evil.example"}},
        httplib::Headers{{"Origin", "http://127.0.0.1:9"}, {"Sec-Fetch-Site", "same-site"}},
        httplib::Headers{{"Sec-Fetch-Site", "cross-site"}}}) {
    auto res = http.Get(def.c_str(), h);
    REQUIRE(res);
    CHECK(res->status == 403);
    CHECK(res->get_header_value("Access-Control-Allow-Origin").empty());
    const json body = json::parse(res->body);
    CHECK(body["error"]["code"] == "cross_origin");
    CHECK(body.contains("candidates"));  // still the answer's shape
  }
  auto pre = http.Options("/sempre", httplib::Headers{{"Origin", "http://evil.example"},
                                                      {"Access-Control-Request-Method", "GET"}});
  REQUIRE(pre);
  CHECK(pre->status == 403);
  SempreReply d = sempre_get(http, "(:dictionary)", "eve");
  CHECK(d.body["stats"]["dictionary"] == "[]");
  // A program (no Origin, no fetch metadata) defines.
  CHECK(sempre_get_target(http, def).body["stats"]["rules"] == 1);

  StudioServer open(fresh_dir("sempre-open"), {"serve.sempre=true", "serve.sempre_origins=['*']"});
  auto o = open.client();
  o.set_url_encode(false);
  auto res = o.Get(sempre_target("(:dictionary)", "x").c_str(),
                   httplib::Headers{{"Origin", "http://evil.example"}});
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Access-Control-Allow-Origin") == "http://evil.example");
}

TEST_CASE("serve.sempre with a study is a bad config") {
  testsupport::ChildProcess serve(
      {std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", "serve", "--set", "serve.port=0", "--set",
       "serve.sempre=true", "--set",
       "serve.study=" + std::string(FLIPPER_SOURCE_DIR) + "/examples/study/study.yaml"});
  // A refusing server prints nothing on stdout; one that serves announces its port there.
  const std::string line = serve.read_line(std::chrono::seconds(30));
  if (!line.empty()) {
    serve.kill_now();
    FAIL("serve started instead of refusing the config: " << line);
  }
  CHECK(serve.finish() == 2);
}

}  // namespace flipper::sempretest
