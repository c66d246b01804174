// The crowd through the server (the naturalization crowd test over HTTP): many concurrent clients,
// each its own session and user, define, query, accept and delete on one `flipper serve`; then the
// server is killed. Every acknowledged rule that was not deleted is in the store, every
// acknowledged deletion stays deleted, and SQLite's integrity check passes.
#include <atomic>
#include <mutex>
#include <set>
#include <thread>

#include "sqlite_integrity.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

struct Ledger {
  std::mutex mutex;
  std::set<std::string> live, deleted;
  int errors = 0;
  std::string first_error;
};

void client(int me, int port, Ledger& ledger) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(60);
  http.set_tcp_nodelay(true);
  auto call = [&](const std::string& session, const json& req) {
    auto res = http.Post(
        session.empty() ? "/api/v1/request" : ("/api/v1/request?session=" + session).c_str(),
        req.dump(), "application/json");
    if (!res || res->status != 200) {
      std::lock_guard lock(ledger.mutex);
      if (ledger.errors++ == 0)
        ledger.first_error = req.dump() + " -> " +
                             (res ? std::to_string(res->status) + " " + res->body
                                  : "no answer: " + httplib::to_string(res.error()));
      return std::make_pair(std::string(), json::object());
    }
    return std::make_pair(res->get_header_value("Flipper-Session"), json::parse(res->body));
  };
  const std::string session = call("", json{{"op", "state"}}).first;
  call(session, json{{"op", "user"}, {"name", "crowd" + std::to_string(me)}});
  std::vector<std::string> mine;
  for (int i = 0; i < 12; ++i) {
    const std::string head = "crowd" + std::to_string(me) + " hop " + std::to_string(i);
    const auto [s1, d] =
        call(session, json{{"op", "define"}, {"head", head}, {"body", {"move up; move down"}}});
    if (d.value("ok", false)) {
      std::lock_guard lock(ledger.mutex);
      for (const auto& r : d["rules"]) {
        ledger.live.insert(r["id"].get<std::string>());
        mine.push_back(r["id"]);
      }
    }
    const auto [s2, q] = call(session, json{{"op", "query"}, {"text", "move left; move right"}});
    if (q.value("ok", false) && !q["candidates"].empty())
      call(session, json{{"op", "accept"}, {"rank", 0}});
    if (i % 3 == 2 && !mine.empty()) {
      const std::string id = mine.back();
      mine.pop_back();
      const auto [s3, del] = call(session, json{{"op", "delete_rule"}, {"rule", id}});
      if (del.value("ok", false)) {
        std::lock_guard lock(ledger.mutex);
        ledger.live.erase(id);
        ledger.deleted.insert(id);
      }
    }
  }
}

TEST_CASE(
    "many concurrent HTTP clients lose no acknowledged rule, even when the server is killed") {
  const std::string dir = fresh_dir("crowd");
  Ledger ledger;
  {
    StudioServer server(dir, {"serve.threads=32"});
    std::vector<std::thread> clients;
    for (int i = 0; i < 16; ++i) clients.emplace_back(client, i, server.port(), std::ref(ledger));
    for (auto& t : clients) t.join();
    server.kill();  // SIGKILL: no clean shutdown
  }
  INFO("first error: " << ledger.first_error);
  CHECK(ledger.errors == 0);
  CHECK(ledger.live.size() >= 16 * 8);  // 12 defines - 4 deletes per client, ≥ 1 rule each
  CHECK(testsupport::sqlite_integrity(dir + "/lexicon.sqlite") == "ok");
  StudioServer server(dir);
  auto http = server.client();
  const Reply rules = post(http, new_session(http), R"({"op":"rules"})");
  std::set<std::string> stored;
  for (const auto& r : rules.body["rules"]) stored.insert(r["id"].get<std::string>());
  std::size_t lost = 0, resurrected = 0;
  for (const auto& id : ledger.live) lost += stored.count(id) ? 0 : 1;
  for (const auto& id : ledger.deleted) resurrected += stored.count(id);
  CHECK(lost == 0);
  CHECK(resurrected == 0);
}

}  // namespace
}  // namespace flipper::studiotest
