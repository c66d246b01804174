// Safety of `flipper serve`: static paths cannot escape the page's directory, world files cannot
// escape the config's world directory, request size and rate limits, same-origin checks, one
// session cannot act as another session's user, and a killed server keeps every acknowledged
// definition.
#include <cstdio>
#include <set>

#include "cli_test_support.hpp"
#include "flipper/studio/server.hpp"
#include "product_schema.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

TEST_CASE("static paths cannot reach files outside the page's directory") {
  StudioServer server(fresh_dir("traversal"));
  auto http = server.client();
  for (const char* path :
       {"/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
        "/..%2f..%2f..%2f..%2fetc%2fpasswd", "/index.html/../../../../etc/passwd",
        "/....//....//etc/passwd", "//etc/passwd", "/%252e%252e/etc/passwd", "/../CMakeLists.txt",
        "/../src/server.cpp", "/%00index.html"}) {
    INFO(path);
    auto res = http.Get(path);
    if (!res) continue;  // httplib may refuse to send a malformed path at all
    CHECK((res->status == 404 || res->status == 400));
    CHECK(res->body.find("root:") == std::string::npos);
    CHECK(res->body.find("add_library") == std::string::npos);
  }
}

TEST_CASE("a world file must lie in the config's world directory") {
  StudioServer server(fresh_dir("worldfile"));
  auto http = server.client();
  const std::string s = new_session(http);
  for (const char* file : {"../../../../../../etc/passwd", "/etc/passwd", "../default.yaml",
                           "../grammars/core.grammar"}) {
    INFO(file);
    const Reply r = post_json(http, s, json{{"op", "world"}, {"file", file}});
    CHECK(r.body["ok"] == false);
    CHECK(r.body["error"]["code"] == "forbidden");
    CHECK(r.text.find("root:") == std::string::npos);
  }
  const Reply ok = post_json(http, s, json{{"op", "world"}, {"file", "study2018.json"}});
  CHECK(ok.body["ok"] == true);
  CHECK(ok.body["world"]["robot"]["x"] == 2);
}

TEST_CASE("bodies over serve.max_request_bytes are refused with 413") {
  StudioServer server(fresh_dir("size"), {"serve.max_request_bytes=1024"});
  auto http = server.client();
  const std::string s = new_session(http);
  std::string text(1000 - 30, 'x');
  const std::string fits = json{{"op", "query"}, {"text", text}}.dump();
  REQUIRE(fits.size() <= 1024);
  CHECK(post(http, s, fits).status == 200);
  const std::string big = json{{"op", "query"}, {"text", std::string(2000, 'x')}}.dump();
  const Reply r = post(http, s, big);
  CHECK(r.status == 413);
  CHECK(r.body["error"]["code"] == "request_too_large");
  CHECK(post(http, s, R"({"op":"state"})").status == 200);  // the server goes on
}

TEST_CASE("more requests than serve.rate_per_second allows are refused with 429") {
  StudioServer server(fresh_dir("rate"), {"serve.rate_per_second=1", "serve.rate_burst=5"});
  auto http = server.client();
  const Reply first = post(http, "", R"({"op":"state"})");
  int ok = 1, limited = 0;
  for (int i = 0; i < 7; ++i) {
    const Reply r = post(http, first.session, R"({"op":"state"})");
    if (r.status == 200) ++ok;
    if (r.status == 429) {
      ++limited;
      CHECK(r.body["error"]["code"] == "rate_limited");
    }
  }
  CHECK(ok == 5);  // the burst; at 1/s at most one more could refill in the loop's few ms
  CHECK(limited == 3);
  // Another session has its own bucket.
  CHECK(post(http, "", R"({"op":"state"})").status == 200);
}

TEST_CASE("state-changing requests from another origin are refused") {
  StudioServer server(fresh_dir("origin"));
  auto http = server.client();
  const std::string s = new_session(http);
  const std::string define = R"({"op":"define","head":"go home","body":["visit room1"]})";
  Reply r = post(http, s, define, {{"Origin", "http://evil.example"}});
  CHECK(r.status == 403);
  CHECK(r.body["error"]["code"] == "cross_origin");
  r = post(http, s, define, {{"Origin", "http://127.0.0.1:1"}});  // another port: another origin
  CHECK(r.status == 403);
  r = post(http, s, define, {{"Origin", "null"}});
  CHECK(r.status == 403);
  r = post(http, s, define, {{"Sec-Fetch-Site", "cross-site"}});
  CHECK(r.status == 403);
  CHECK(post(http, s, R"({"op":"rules"})").body["rules"].empty());  // nothing was defined
  r = post(http, s, define, {{"Origin", server.origin()}, {"Sec-Fetch-Site", "same-origin"}});
  CHECK(r.status == 200);
  CHECK(r.body["ok"] == true);
}

TEST_CASE("a session cannot act as another session's user") {
  StudioServer server(fresh_dir("users"));
  server.add_account("ana", "ana's password");
  auto http = server.client();
  const auto as_ana = cookie(login(http, json{{"name", "ana"}, {"password", "ana's password"}}));
  const std::string ana = new_session(http, as_ana), eve = new_session(http);
  CHECK(post(http, ana, R"({"op":"state"})", as_ana).user == "ana");
  const Reply defined =
      post(http, ana,
           R"({"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]})", as_ana);
  REQUIRE(defined.body["ok"] == true);
  const std::string rule = defined.body["rules"][0]["id"];
  // eve (a guest) cannot become ana, nor another guest, nor any name of her choosing.
  Reply r = post(http, eve, R"({"op":"user","name":"ana"})");
  CHECK(r.body["ok"] == false);
  CHECK(r.body["error"]["code"] == "forbidden");
  CHECK(r.user == "guest-1");
  CHECK(post(http, eve, R"({"op":"user","name":"guest-9"})").body["error"]["code"] == "forbidden");
  CHECK(post(http, eve, R"({"op":"user","name":"zed"})").body["error"]["code"] == "forbidden");
  // ... so she cannot delete ana's rule.
  r = post_json(http, eve, json{{"op", "delete_rule"}, {"rule", rule}});
  CHECK(r.body["error"]["code"] == "forbidden");
  // ana's session token alone is not enough: it needs ana's login.
  r = post_json(http, ana, json{{"op", "delete_rule"}, {"rule", rule}});
  CHECK(r.status == 401);
  CHECK(r.body["error"]["code"] == "login_required");
  // ana deletes her rule.
  CHECK(post(http, ana, json{{"op", "delete_rule"}, {"rule", rule}}.dump(), as_ana).body["ok"] ==
        true);
}

TEST_CASE("sessions are bounded by serve.max_sessions") {
  StudioServer server(fresh_dir("max-sessions"), {"serve.max_sessions=3"});
  auto http = server.client();
  for (int i = 0; i < 3; ++i) new_session(http);
  const Reply r = post(http, "", R"({"op":"state"})");
  CHECK(r.status == 503);
  CHECK(r.body["error"]["code"] == "too_many_sessions");
}

TEST_CASE("a killed server loses no acknowledged definition") {
  const std::string dir = fresh_dir("kill");
  std::vector<std::string> acknowledged;
  std::string as_ana;  // the login survives the restarts (docs/accounts.md)
  for (int round = 0; round < 5; ++round) {
    StudioServer server(dir);
    if (round == 0) server.add_account("ana", "ana's password");
    auto http = server.client();
    if (round == 0) as_ana = login(http, json{{"name", "ana"}, {"password", "ana's password"}});
    const std::string s = new_session(http, cookie(as_ana));
    REQUIRE(post(http, s, R"({"op":"state"})", cookie(as_ana)).user == "ana");
    // Every definition defined so far is there after the restart.
    const Reply rules = post(http, s, R"({"op":"rules"})", cookie(as_ana));
    std::vector<std::string> heads;
    for (const auto& r : rules.body["rules"]) heads.push_back(r["head"]);
    for (const auto& h : acknowledged) {
      INFO("round " << round << ": " << h);
      CHECK(std::find(heads.begin(), heads.end(), h) != heads.end());
    }
    // A few more, each acknowledged before the next; then SIGKILL right after the last answer.
    for (int i = 0; i < 4; ++i) {
      const std::string head = "hop " + std::to_string(round * 4 + i) + " times";
      const Reply d = post(
          http, s, json{{"op", "define"}, {"head", head}, {"body", {"move up; move down"}}}.dump(),
          cookie(as_ana));
      if (d.status == 200 && d.body["ok"] == true) acknowledged.push_back(head);
    }
    server.kill();
  }
  CHECK(acknowledged.size() == 20);
  StudioServer server(dir);
  auto http = server.client();
  const Reply rules = post(http, new_session(http), R"({"op":"rules"})");
  std::set<std::string> heads;
  for (const auto& r : rules.body["rules"]) heads.insert(r["head"].get<std::string>());
  for (const auto& h : acknowledged) CHECK(heads.count(h) == 1);
}

TEST_CASE("binding anything but loopback warns with the address") {
  CHECK(studio::is_loopback("127.0.0.1"));
  CHECK(studio::is_loopback("127.8.9.10"));
  CHECK(studio::is_loopback("::1"));
  CHECK(studio::is_loopback("localhost"));
  CHECK_FALSE(studio::is_loopback("0.0.0.0"));
  CHECK_FALSE(studio::is_loopback("::"));
  CHECK_FALSE(studio::is_loopback("192.168.1.20"));
  CHECK_FALSE(studio::is_loopback("128.0.0.1"));
  // 192.0.2.1 (TEST-NET-1) is no address of this machine: the warning, then a clean failure.
  const auto r = clitest::run_flipper(
      "serve --set serve.host=192.0.2.1 --set serve.port=0 --set lexicon.path=:memory:");
  CHECK(r.status == 1);
  CHECK(clitest::contains(r.out, "warning: listening on 192.0.2.1, which is not a loopback"));
  CHECK(clitest::contains(r.out, "serve_failed"));
}

TEST_CASE("serve keys are validated like every kernel key") {
  auto r = clitest::run_flipper("serve --set serve.port=70000 --set lexicon.path=:memory:");
  CHECK(r.status == 2);
  CHECK(clitest::contains(r.out, "serve.port"));
  r = clitest::run_flipper("serve --set serve.threds=4 --set lexicon.path=:memory:");
  CHECK(r.status == 2);
  CHECK(clitest::contains(r.out, "serve.threads"));  // the "did you mean"
}

TEST_CASE("serve options start from the kernel schema's defaults") {
  const sdk::ParamSchema& schema = kernel::Config::schema();
  const auto def = [&](const char* key) {
    const sdk::ParamSpec* spec = schema.find(key);
    REQUIRE(spec != nullptr);
    REQUIRE(spec->default_value.has_value());
    return *spec->default_value;
  };
  const auto integer = [&](const char* key) { return std::get<std::int64_t>(def(key)); };
  const studio::ServeOptions o;
  CHECK(o.host == std::get<std::string>(def("serve.host")));
  CHECK(o.port == integer("serve.port"));
  CHECK(o.threads == integer("serve.threads"));
  CHECK(static_cast<std::int64_t>(o.max_request_bytes) == integer("serve.max_request_bytes"));
  CHECK(o.rate_per_second == static_cast<double>(integer("serve.rate_per_second")));
  CHECK(o.rate_burst == static_cast<double>(integer("serve.rate_burst")));
  CHECK(static_cast<std::int64_t>(o.max_sessions) == integer("serve.max_sessions"));
  CHECK(o.session_idle_s == integer("serve.session_idle_s"));
  // A config that sets nothing reads back the same.
  const studio::ServeOptions read =
      studio::ServeOptions::from_config(kernel::Config::embedded_default());
  CHECK(read.host == o.host);
  CHECK(read.port == o.port);
  CHECK(read.max_sessions == o.max_sessions);
}

}  // namespace
}  // namespace flipper::studiotest
