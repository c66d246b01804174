// The attacks on `flipper serve` that once worked (docs/studio.md, docs/accounts.md), each
// against the real binary on loopback: taking over a name after a restart or an eviction,
// DNS rebinding, slow and idle clients, HTTP framing tricks, a session flood, a memory flood.
// Figures (how long, how much) are in bench/serve; these check what is refused and that the
// refusal comes at once.
#include <chrono>
#include <thread>

#include "raw_socket.hpp"
#include "sanitizer_build.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const json kAnaLogin{{"name", "ana"}, {"password", "ana's password"}};

std::string define_as(httplib::Client& http, const std::string& session,
                      const httplib::Headers& who) {
  const Reply d =
      post(http, session,
           R"({"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]})", who);
  REQUIRE(d.body["ok"] == true);
  return d.body["rules"][0]["id"];
}

TEST_CASE("after a restart nobody else can take ana's name or delete her rules") {
  const std::string dir = fresh_dir("takeover-restart");
  std::string rule, as_ana;
  {
    StudioServer server(dir);
    server.add_account("ana", "ana's password");
    auto http = server.client();
    as_ana = login(http, kAnaLogin);
    REQUIRE(!as_ana.empty());
    rule = define_as(http, new_session(http, cookie(as_ana)), cookie(as_ana));
  }
  StudioServer server(dir);
  auto http = server.client();
  // The attack: a fresh session names itself ana, then deletes her rule.
  const std::string eve = new_session(http);
  const Reply named = post(http, eve, R"({"op":"user","name":"ana"})");
  CHECK(named.body["error"]["code"] == "forbidden");
  const Reply deleted = post_json(http, eve, json{{"op", "delete_rule"}, {"rule", rule}});
  CHECK(deleted.body["error"]["code"] == "forbidden");
  // A wrong password opens nothing; ana's cookie still works after the restart.
  int status = 0;
  CHECK(login(http, json{{"name", "ana"}, {"password", "guess"}}, &status).empty());
  CHECK(status == 401);
  const std::string mine = new_session(http, cookie(as_ana));
  CHECK(post(http, mine, json{{"op", "delete_rule"}, {"rule", rule}}.dump(), cookie(as_ana))
            .body["ok"] == true);
}

TEST_CASE("after an eviction nobody else can take ana's name") {
  StudioServer server(fresh_dir("takeover-evict"),
                      {"serve.max_sessions=1", "serve.session_idle_s=1"});
  server.add_account("ana", "ana's password");
  auto http = server.client();
  const auto as_ana = cookie(login(http, kAnaLogin));
  const std::string ana = new_session(http, as_ana);
  const std::string rule = define_as(http, ana, as_ana);
  // The server is full (503) until ana's session has been idle for serve.session_idle_s; then
  // a new session evicts it. Polled (a refused attempt costs no new-session token), bounded.
  const auto full_until = Clock::now() + 20s;
  Reply opened = post(http, "", R"({"op":"state"})");
  while (opened.status == 503 && Clock::now() < full_until) {
    CHECK(opened.body["error"]["code"] == "too_many_sessions");
    std::this_thread::sleep_for(50ms);  // the poll's pace
    opened = post(http, "", R"({"op":"state"})");
  }
  REQUIRE(opened.status == 200);  // evicts ana's session (the server is full)
  const std::string eve = opened.session;
  CHECK(post(http, ana, R"({"op":"state"})", as_ana).status == 404);
  CHECK(post(http, eve, R"({"op":"user","name":"ana"})").body["error"]["code"] == "forbidden");
  CHECK(post_json(http, eve, json{{"op", "delete_rule"}, {"rule", rule}}).body["error"]["code"] ==
        "forbidden");
}

TEST_CASE("guest names are never given twice, not even after a restart") {
  const std::string dir = fresh_dir("guests");
  std::string rule;
  {
    StudioServer server(dir);
    auto http = server.client();
    const Reply first = post(http, "", R"({"op":"state"})");
    CHECK(first.user == "guest-1");
    rule = define_as(http, first.session, {});
  }
  StudioServer server(dir);
  auto http = server.client();
  const Reply next = post(http, "", R"({"op":"state"})");
  CHECK(next.user == "guest-2");
  CHECK(post_json(http, next.session, json{{"op", "delete_rule"}, {"rule", rule}})
            .body["error"]["code"] == "forbidden");
}

TEST_CASE("account names are validated and reach headers only in a safe form") {
  StudioServer server(fresh_dir("names"));
  for (const std::string& bad :
       std::vector<std::string>{"'ana x'", "'ana\nx'", std::string(33, 'a'), "guest-3", "anonymous",
                                "'.ana'", "'ana;x'", "'a b'"}) {
    INFO(bad);
    const auto r = server.run_accounts("add " + bad, "long enough\n");
    CHECK(r.status == 2);
    CHECK(r.out.find("[bad_name]") != std::string::npos);
  }
  CHECK(server.run_accounts("add " + std::string(32, 'a'), "long enough\n").status == 0);
  CHECK(server.run_accounts("add bob", "short\n").status == 2);  // weak_password
  const auto dup = server.run_accounts("add " + std::string(32, 'a'), "long enough\n");
  CHECK(dup.status == 1);
  CHECK(dup.out.find("[account_exists]") != std::string::npos);
}

TEST_CASE("one-time codes log in once, logout and revoke end a login") {
  StudioServer server(fresh_dir("codes"), {"serve.guests=false"});
  auto http = server.client();
  // No guests: nothing without a login.
  Reply r = post(http, "", R"({"op":"state"})");
  CHECK(r.status == 401);
  CHECK(r.body["error"]["code"] == "login_required");
  const auto invited = server.run_accounts("invite p17 --url http://127.0.0.1:1/");
  REQUIRE(invited.status == 0);
  const std::string code = invited.out.substr(0, invited.out.find('\n'));
  CHECK(code.size() == 32);
  CHECK(invited.out.find("http://127.0.0.1:1/?code=" + code) != std::string::npos);
  auto res = http.Post("/api/v1/login", json{{"code", code}}.dump(), "application/json");
  REQUIRE(res);
  CHECK(res->status == 200);
  const std::string set = res->get_header_value("Set-Cookie");
  CHECK(set.find("HttpOnly") != std::string::npos);
  CHECK(set.find("SameSite=Strict") != std::string::npos);
  CHECK(set.find(code) == std::string::npos);  // the cookie is a new token, not the code
  const auto as_p17 = cookie(set.substr(0, set.find(';')));
  int status = 0;
  CHECK(login(http, json{{"code", code}}, &status).empty());  // used
  CHECK(status == 401);
  const std::string s = new_session(http, as_p17);
  CHECK(post(http, s, R"({"op":"state"})", as_p17).user == "p17");
  // Revoked from the command line: the next request needs a new login.
  CHECK(server.run_accounts("revoke p17").out.find("revoked 1") != std::string::npos);
  r = post(http, s, R"({"op":"state"})", as_p17);
  CHECK(r.status == 401);
  // A second code, then a logout.
  const auto again = server.run_accounts("invite p17");
  const auto as_again =
      cookie(login(http, json{{"code", again.out.substr(0, again.out.find('\n'))}}));
  CHECK(post(http, "", R"({"op":"state"})", as_again).status == 200);
  auto out = http.Post("/api/v1/logout", as_again, "", "application/json");
  REQUIRE(out);
  CHECK(out->get_header_value("Set-Cookie").find("Max-Age=0") != std::string::npos);
  CHECK(post(http, "", R"({"op":"state"})", as_again).status == 401);
}

TEST_CASE("an administrator may delete anyone's rule") {
  StudioServer server(fresh_dir("admin"));
  server.add_account("ana", "ana's password");
  server.add_account("mod", "moderator pass", "admin");
  auto http = server.client();
  const auto as_ana = cookie(login(http, kAnaLogin));
  const std::string rule = define_as(http, new_session(http, as_ana), as_ana);
  const auto as_mod = cookie(login(http, json{{"name", "mod"}, {"password", "moderator pass"}}));
  const Reply r = post(http, new_session(http, as_mod),
                       json{{"op", "delete_rule"}, {"rule", rule}}.dump(), as_mod);
  CHECK(r.body["ok"] == true);
  CHECK(r.body["deleted"] == rule);
  const Reply left = post(http, new_session(http, as_ana), R"({"op":"rules"})", as_ana);
  for (const auto& listed : left.body["rules"]) CHECK(listed["id"] != rule);
  auto listed = server.run_accounts("list --json");
  CHECK(listed.out.find(R"("name":"mod","password":true,"role":"admin")") != std::string::npos);
}

TEST_CASE("a rebound host name is refused, the origin is checked against the served names") {
  StudioServer server(fresh_dir("rebinding"), {"serve.allowed_hosts=[studio.example]"});
  const std::string p = std::to_string(server.port());
  const std::string body = R"({"op":"define","head":"go home","body":["visit room1"]})";
  const auto raw = [&](const std::string& host, const std::string& origin) {
    RawSocket s(server.port());
    REQUIRE(s.send("POST /api/v1/request HTTP/1.1\r\nHost: " + host + "\r\nOrigin: " + origin +
                   "\r\nContent-Type: application/json\r\nContent-Length: " +
                   std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body));
    return s.read_all(5s);
  };
  // The DNS-rebinding request: evil.com resolves to 127.0.0.1; Host and Origin agree.
  std::string a = raw("evil.com:" + p, "http://evil.com:" + p);
  CHECK(a.rfind("HTTP/1.1 421", 0) == 0);
  CHECK(a.find("wrong_host") != std::string::npos);
  a = raw("127.0.0.1:" + p, "http://evil.com:" + p);
  CHECK(a.rfind("HTTP/1.1 403", 0) == 0);
  CHECK(a.find("cross_origin") != std::string::npos);
  // The served names: the bound address, localhost, serve.allowed_hosts.
  CHECK(raw("localhost:" + p, "http://localhost:" + p).rfind("HTTP/1.1 200", 0) == 0);
  CHECK(raw("studio.example:" + p, "http://studio.example:" + p).rfind("HTTP/1.1 200", 0) == 0);
  const std::string other_port = std::to_string(server.port() + 1);
  CHECK(raw("studio.example:" + other_port, "").rfind("HTTP/1.1 421", 0) == 0);
  CHECK(raw("", "").rfind("HTTP/1.1 421", 0) == 0);  // no Host at all
}

TEST_CASE("framing tricks are refused at once, pipelined requests answered in order") {
  StudioServer server(fresh_dir("framing"));
  const std::string host = "Host: 127.0.0.1:" + std::to_string(server.port()) + "\r\n";
  const std::string state = R"({"op":"state"})";
  const auto answer = [&](const std::string& request) {
    RawSocket s(server.port());
    REQUIRE(s.send(request));
    const auto start = Clock::now();
    bool closed = false;
    const std::string out = s.read_all(5s, &closed);
    CHECK(closed);                     // the connection ends with the refusal
    CHECK(Clock::now() - start < 2s);  // at once, not after a read timeout
    return out;
  };
  std::string a = answer("POST /api/v1/request HTTP/1.1\r\n" + host +
                         "Content-Length: 14\r\nContent-Length: 5\r\n\r\n" + state);
  CHECK(a.rfind("HTTP/1.1 400", 0) == 0);
  CHECK(a.find("bad_content_length") != std::string::npos);
  a = answer("POST /api/v1/request HTTP/1.1\r\n" + host + "Content-Length: -1\r\n\r\n");
  CHECK(a.rfind("HTTP/1.1 400", 0) == 0);
  a = answer("POST /api/v1/request HTTP/1.1\r\n" + host + "Content-Length: 99999999999999\r\n\r\n");
  CHECK(a.rfind("HTTP/1.1 413", 0) == 0);
  a = answer("POST /api/v1/request HTTP/1.1\r\n" + host + "Transfer-Encoding: gzip\r\n\r\n");
  CHECK(a.rfind("HTTP/1.1 501", 0) == 0);
  a = answer("POST /api/v1/request HTTP/1.1\r\n" + host +
             "Transfer-Encoding: chunked\r\nContent-Length: 14\r\n\r\n0\r\n\r\n");
  CHECK(a.rfind("HTTP/1.1 400", 0) == 0);
  // Three requests in one write: three answers, in order, on the same connection.
  std::string three;
  for (int id = 1; id <= 3; ++id) {
    const std::string b = json{{"op", "state"}, {"id", id}}.dump();
    three += "POST /api/v1/request HTTP/1.1\r\n" + host +
             "Content-Length: " + std::to_string(b.size()) + "\r\n\r\n" + b;
  }
  RawSocket s(server.port());
  REQUIRE(s.send(three));
  std::string got;
  for (int i = 0; i < 50 && count_answers(got) < 3; ++i) got += s.read_all(200ms);
  REQUIRE(count_answers(got) == 3);
  const auto first = got.find(R"("id":1)"), second = got.find(R"("id":2)"),
             third = got.find(R"("id":3)");
  CHECK(first < second);
  CHECK(second < third);
  CHECK(third != std::string::npos);
}

TEST_CASE("slow clients are cut at the request deadline and capped per address") {
  StudioServer server(fresh_dir("slow"),
                      {"serve.request_timeout_ms=500", "serve.max_connections_per_address=40"});
  const std::string host = "Host: 127.0.0.1:" + std::to_string(server.port()) + "\r\n";
  // 40 connections from 127.0.0.2 each trickle a header line every 100 ms (every read is quick:
  // only the total deadline can end them).
  std::vector<RawSocket> slow;
  for (int i = 0; i < 40; ++i) {
    slow.emplace_back(server.port(), "127.0.0.2");
    REQUIRE(slow.back().send("POST /api/v1/request HTTP/1.1\r\n"));
  }
  // The 41st from that address is refused at once.
  RawSocket extra(server.port(), "127.0.0.2");
  bool closed = false;
  const std::string refused = extra.read_all(2s, &closed);
  CHECK(refused.rfind("HTTP/1.1 503", 0) == 0);
  CHECK(refused.find("serve.max_connections_per_address") != std::string::npos);
  // Another address is served meanwhile.
  auto http = server.client();
  CHECK(post(http, "", R"({"op":"state"})").status == 200);
  // Trickling does not keep a connection: all are closed once 500 ms have passed.
  const auto start = Clock::now();
  int open = 40;
  while (open > 0 && Clock::now() - start < 5s) {
    open = 0;
    for (auto& s : slow)
      if (s.send("X-Slow: 1\r\n")) ++open;
    std::this_thread::sleep_for(100ms);  // the trickle's pace
  }
  CHECK(open == 0);
  CHECK(Clock::now() - start < 3s);
}

TEST_CASE("a session flood from one address does not lock out others") {
  StudioServer server(fresh_dir("flood"));
  auto http = server.client();
  int created = 0, refused = 0;
  for (int i = 0; i < 980; ++i) {
    const Reply r = post(http, "", R"({"op":"state"})");
    if (r.status == 200) ++created;
    if (r.status == 429) {
      ++refused;
      if (refused == 1) {
        CHECK(r.body["error"]["code"] == "too_many_sessions");
        CHECK(r.text.find("serve.sessions_per_address") != std::string::npos);
      }
    }
  }
  CHECK(created == 32);  // serve.sessions_per_address
  CHECK(refused == 980 - 32);
  // A new user from another address gets a session.
  RawSocket other(server.port(), "127.0.0.3");
  const std::string body = R"({"op":"state"})";
  REQUIRE(other.send("POST /api/v1/request HTTP/1.1\r\nHost: 127.0.0.1:" +
                     std::to_string(server.port()) + "\r\nContent-Length: " +
                     std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body));
  CHECK(other.read_all(10s).rfind("HTTP/1.1 200", 0) == 0);
}

// A world of side x side free cells (the default grid2d plugin), as a world object.
std::string square_world(int side) {
  const std::string max = std::to_string(side - 1);
  return R"({"op":"world","world":{"walls":[],"robot":{"x":0,"y":0,"holding":[]},"items":[],)"
         R"("bounds":{"min":[0,0],"max":[)" +
         max + "," + max + "]}}}";
}

long rss_kib(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

TEST_CASE("maximal worlds are refused before the memory budget is crossed") {
  // world.max_cells = 2048^2 (the default 4194304): a maximal world is charged 80 MiB; one
  // kernel over an empty store takes 4 MiB of the budget (docs/studio.md §5).
  StudioServer server(fresh_dir("memory"), {"serve.memory_budget_mb=204", "serve.kernels=1",
                                            "serve.evict_after_s=3600"});
  auto http = server.client();
  const long before = rss_kib(server.pid());
  std::vector<std::string> sessions;
  int loaded = 0, busy = 0;
  for (int i = 0; i < 6; ++i) {
    const std::string s = new_session(http);
    sessions.push_back(s);
    const Reply r = post(http, s, square_world(2048));
    if (r.body["ok"] == true) ++loaded;
    if (r.body["ok"] == false && r.body["error"]["code"] == "server_busy") {
      ++busy;
      CHECK(r.text.find("serve.memory_budget_mb") != std::string::npos);
    }
  }
  // Two fit (2 x 80 MiB reserved + the sessions' 64 KiB each); each further one would cross.
  CHECK(loaded == 2);
  CHECK(busy == 4);
  // Resident memory stays under the budget; ASan's shadow memory and redzones add ~10 %, so the
  // instrumented run checks the refusals above and the Release run this bound.
  if (!testsupport::kAddressSanitizer) CHECK(rss_kib(server.pid()) - before < 200 * 1024);
}

TEST_CASE("every kernel of the pool is charged to the memory budget") {
  // 3 kernels x 4 MiB (empty store) leave 173 - 12 = 161 MiB: two maximal worlds (2 x 80 MiB,
  // plus 64 KiB for each session) fit; with one MiB less of budget (160 MiB) only one does.
  for (const auto& [budget, fit] : {std::pair{173, 2}, std::pair{172, 1}}) {
    StudioServer server(fresh_dir("memory-kernels"),
                        {"serve.memory_budget_mb=" + std::to_string(budget), "serve.kernels=3",
                         "serve.evict_after_s=3600"});
    auto http = server.client();
    int loaded = 0;
    for (int i = 0; i < 3; ++i)
      loaded += post(http, new_session(http), square_world(2048)).body["ok"] == true;
    CHECK(loaded == fit);
  }
}

TEST_CASE("a pool whose kernels would take more than half the budget is a bad config") {
  // 4 x 4 MiB (empty store) = 16 MiB: half of 32 MiB is allowed, half of 31 MiB is not.
  StudioServer fits(fresh_dir("kernels-budget"), {"serve.kernels=4", "serve.memory_budget_mb=32"});
  CHECK(fits.port() > 0);
  const std::string cmd = "timeout 20 " + std::string(FLIPPER_BINARY_DIR) +
                          "/bin/flipper serve --set serve.port=0 --set serve.kernels=4 "
                          "--set serve.memory_budget_mb=31 --set lexicon.path=" +
                          fresh_dir("kernels-budget") + "/lexicon.sqlite 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  const int raw = ::pclose(p);
  CHECK(WEXITSTATUS(raw) == 2);
  CHECK(out.find("[bad_config]") != std::string::npos);
  CHECK(out.find("serve.kernels") != std::string::npos);
}

TEST_CASE("the memory budget evicts idle guests first") {
  StudioServer server(fresh_dir("memory-evict"),
                      {"serve.memory_budget_mb=204", "serve.kernels=1", "serve.evict_after_s=0"});
  auto http = server.client();
  const std::string a = new_session(http), b = new_session(http), c = new_session(http);
  REQUIRE(post(http, a, square_world(2048)).body["ok"] == true);
  REQUIRE(post(http, b, square_world(2048)).body["ok"] == true);
  // c's world needs room: a (idle the longest) is evicted.
  CHECK(post(http, c, square_world(2048)).body["ok"] == true);
  CHECK(post(http, a, R"({"op":"state"})").status == 404);
  CHECK(post(http, b, R"({"op":"state"})").status == 200);
}

}  // namespace
}  // namespace flipper::studiotest
