// The HTTP transport answers exactly what `flipper session` answers (docs/protocol.md), with the
// HTTP statuses of docs/serve.md; the page's files are served from memory.
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

// The timing field differs from run to run; everything else must be identical.
json without_ms(json a) {
  if (a.is_object()) {
    a.erase("ms");
    for (auto& [k, v] : a.items()) v = without_ms(v);
  } else if (a.is_array()) {
    for (auto& v : a) v = without_ms(v);
  }
  return a;
}

const std::vector<std::pair<std::string, int>> kScript = {
    {R"({"op":"user","name":"ana"})", 200},
    {R"({"op":"state","id":1})", 200},
    {R"({"op":"query","text":"visit world containing item is red; pick item is red","id":"q1"})",
     200},
    {R"({"op":"accept","rank":0})", 200},
    {R"({"op":"query","text":"pick 3 items"})", 200},
    {R"({"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]})", 200},
    {R"({"op":"query","text":"drop 2 items","k":2})", 200},
    {R"({"op":"accept","rank":0})", 200},
    {R"({"op":"rules"})", 200},
    {R"({"op":"delete_rule","rule":"no-such-rule"})", 200},
    {R"({"op":"accept","rank":7})", 200},
    {R"({"op":"define","head":"move up","body":["move up"]})", 200},
    {R"({"op":"frobnicate","id":[1,2]})", 400},
    {R"({"op":"query"})", 400},
    {R"({"op":"query","text":5})", 400},
    {R"(not json)", 400},
    {R"([1,2,3])", 400},
    {R"({"op":"world","world":{"walls":[[1,1]],"robot":{"x":0,"y":0,"holding":[]},"items":[],"bounds":{"min":[0,0],"max":[3,3]}}})",
     200},
    {R"({"op":"world","world":{"walls":[[0,0]],"robot":{"x":0,"y":0,"holding":[]},"items":[]}})",
     200},
    {R"({"op":"query","text":"move up; move right"})", 200},
};

TEST_CASE("POST /api/v1/request answers exactly what flipper session answers") {
  const std::string dir = fresh_dir("same-answers");
  StudioServer server(dir);
  server.add_account("ana", "ana's password");
  auto http = server.client();
  // Over HTTP the session's user is the account logged in (docs/accounts.md): `user` with the
  // same name answers as in `flipper session`.
  const auto as_ana = cookie(login(http, json{{"name", "ana"}, {"password", "ana's password"}}));
  testsupport::ChildProcess cli({std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", "session",
                                 "--set", "lexicon.path=" + dir + "/cli.sqlite", "--set",
                                 "lexicon.preload="});
  std::string session;
  for (const auto& [request, status] : kScript) {
    INFO(request);
    const Reply r = post(http, session, request, as_ana);
    session = r.session;
    REQUIRE(cli.write_line(request));
    const json expected = json::parse(cli.read_line());
    CHECK(r.status == status);
    REQUIRE_FALSE(r.body.is_discarded());
    CHECK(without_ms(r.body) == without_ms(expected));
  }
  // The define was acknowledged: its rules are in the server's store (ids as `flipper session`).
  const Reply rules = post(http, session, R"({"op":"rules"})", as_ana);
  REQUIRE(rules.body["rules"].size() == 2);
  CHECK(rules.body["rules"][0]["author"] == "ana");
}

TEST_CASE("a new session gets an unguessable token and its own guest user") {
  StudioServer server(fresh_dir("tokens"));
  auto http = server.client();
  const Reply a = post(http, "", R"({"op":"state"})");
  const Reply b = post(http, "", R"({"op":"state"})");
  CHECK(a.session.size() == 32);
  CHECK(a.session.find_first_not_of("0123456789abcdef") == std::string::npos);
  CHECK(a.session != b.session);
  CHECK(a.user == "guest-1");
  CHECK(b.user == "guest-2");
  // The token names the session: its pending query belongs to it alone.
  REQUIRE(post(http, a.session, R"({"op":"query","text":"move right"})").body["ok"] == true);
  CHECK(post(http, b.session, R"({"op":"accept","rank":0})").body["error"]["code"] == "no_query");
  const Reply accepted = post(http, a.session, R"({"op":"accept","rank":0})");
  CHECK(accepted.body["world"]["robot"]["x"] == 3);  // (2,4) -> (3,4) on the study map
  CHECK(post(http, b.session, R"({"op":"state"})").body["world"]["robot"]["x"] == 2);
  // An unknown token is refused, never silently replaced.
  const Reply unknown = post(http, std::string(32, '0'), R"({"op":"state"})");
  CHECK(unknown.status == 404);
  CHECK(unknown.body["error"]["code"] == "unknown_session");
}

TEST_CASE("the page's files are served with their types, unknown paths are 404") {
  StudioServer server(fresh_dir("static"));
  auto http = server.client();
  auto index = http.Get("/");
  REQUIRE(index);
  CHECK(index->status == 200);
  CHECK(index->get_header_value("Content-Type") == "text/html; charset=utf-8");
  CHECK(index->body.find("Flipper Studio") != std::string::npos);
  auto js = http.Get("/app.js");
  REQUIRE(js);
  CHECK(js->get_header_value("Content-Type") == "text/javascript; charset=utf-8");
  auto info = http.Get("/api/v1/info");
  REQUIRE(info);
  const json i = json::parse(info->body);
  CHECK(i["sharing"] == "shared");
  // two-floors.json is a 3-D world: the default (grid2d) server cannot load it, so it is no choice.
  CHECK(i["worlds"] == json::array({"study2018.json"}));
  const auto& words = i["vocabulary"];
  CHECK(std::find(words.begin(), words.end(), "visit") != words.end());
  CHECK(std::find(words.begin(), words.end(), "triangle") != words.end());
  auto missing = http.Get("/nope.html");
  REQUIRE(missing);
  CHECK(missing->status == 404);
  CHECK(json::parse(missing->body)["error"]["code"] == "not_found");
  CHECK(server.stop() == 0);  // SIGTERM: a clean stop
}

}  // namespace
}  // namespace flipper::studiotest
