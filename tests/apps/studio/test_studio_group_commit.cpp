// Group commit in `flipper serve` (docs/naturalization.md §5 "Group commit"): many sessions define
// and accept at once on a pool of kernels sharing one store. Every acknowledged define and accept
// is in the store after a SIGKILL right after the last answer (rules and use counters), a request
// that fails inside its write transaction fails alone with its own code, and the kernels' writes
// went through the shared sync (the server's counters at a clean stop).
#include <atomic>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "sqlite_integrity.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest::group_commit {

constexpr int kClients = 8;
constexpr int kDefines = 5;

struct Ledger {
  std::mutex mutex;
  std::map<std::string, std::string> rule_head;  ///< acknowledged rule id -> its head
  std::map<std::string, int> accepts;            ///< head -> acknowledged accepts of its parse
  std::map<std::string, int> refusals;           ///< the failing requests' codes
  int errors = 0;
  std::string first_error;
};

/// Letters only, so induction keeps each head a constant rule of its own.
std::string head_of(int client, int i) {
  return std::string("gc") + static_cast<char>('a' + client) + static_cast<char>('a' + i) + " hop";
}

void client(int me, int port, const std::string& owners_rule, Ledger& ledger) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(60);
  http.set_tcp_nodelay(true);
  auto call = [&](const std::string& session, const json& req) {
    auto res = http.Post(
        session.empty() ? "/api/v1/request" : ("/api/v1/request?session=" + session).c_str(),
        req.dump(), "application/json");
    if (!res) {
      const std::lock_guard lock(ledger.mutex);
      if (ledger.errors++ == 0) ledger.first_error = req.dump() + " -> no answer";
      return std::make_pair(std::string(), json::object());
    }
    return std::make_pair(res->get_header_value("Flipper-Session"), json::parse(res->body));
  };
  auto fail = [&](const json& req, const json& answer) {
    const std::lock_guard lock(ledger.mutex);
    if (ledger.errors++ == 0) ledger.first_error = req.dump() + " -> " + answer.dump();
  };
  const std::string session = call("", json{{"op", "state"}}).first;
  for (int i = 0; i < kDefines; ++i) {
    const std::string head = head_of(me, i);
    const json define{{"op", "define"}, {"head", head}, {"body", {"move left; move right"}}};
    const json d = call(session, define).second;
    if (!d.value("ok", false)) {
      fail(define, d);
      continue;
    }
    {
      const std::lock_guard lock(ledger.mutex);
      for (const auto& r : d["rules"]) ledger.rule_head[r["id"].get<std::string>()] = head;
    }
    const json q = call(session, json{{"op", "query"}, {"text", head}}).second;
    if (!q.value("ok", false) || q["candidates"].empty()) {
      fail(json{{"query", head}}, q);
      continue;
    }
    const json accept{{"op", "accept"}, {"rank", 0}};
    const json a = call(session, accept).second;
    if (a.value("ok", false)) {
      const std::lock_guard lock(ledger.mutex);
      ++ledger.accepts[head];
    } else {
      fail(accept, a);
    }
    if (i == 2) {
      // Another session's (guest's) rule: refused inside the delete's write transaction, amid the
      // others.
      const json del = call(session, json{{"op", "delete_rule"}, {"rule", owners_rule}}).second;
      const std::lock_guard lock(ledger.mutex);
      ++ledger.refusals[del.value("ok", false) ? std::string("ok")
                                               : del["error"]["code"].get<std::string>()];
    }
  }
}

/// Runs the clients against `server` (after one owner's rule exists); returns that rule's id.
std::string run_crowd(StudioServer& server, Ledger& ledger) {
  auto http = server.client();
  const std::string owner = new_session(http);
  const Reply d = post(http, owner, R"({"op":"define","head":"owner hop","body":["move up"]})");
  REQUIRE(d.body.value("ok", false));
  std::string owners_rule = d.body["rules"][0]["id"];
  std::vector<std::thread> clients;
  clients.reserve(kClients);
  for (int i = 0; i < kClients; ++i)
    clients.emplace_back(client, i, server.port(), owners_rule, std::ref(ledger));
  for (auto& t : clients) t.join();
  return owners_rule;
}

TEST_CASE("group commit: concurrent defines and accepts from many sessions survive a SIGKILL") {
  const std::string dir = fresh_dir("group-commit");
  Ledger ledger;
  std::string owners_rule;
  {
    StudioServer server(dir, {"serve.threads=16", "serve.kernels=4"});
    owners_rule = run_crowd(server, ledger);
    server.kill();  // right after the last answer: no clean shutdown
  }
  INFO("first error: " << ledger.first_error);
  CHECK(ledger.errors == 0);
  CHECK(ledger.refusals == std::map<std::string, int>{{"forbidden", kClients}});
  CHECK(ledger.accepts.size() == static_cast<std::size_t>(kClients * kDefines));
  CHECK(testsupport::sqlite_integrity(dir + "/lexicon.sqlite") == "ok");
  StudioServer server(dir);
  auto http = server.client();
  const Reply rules = post(http, new_session(http), R"({"op":"rules"})");
  std::map<std::string, json> stored;
  for (const auto& r : rules.body["rules"]) stored[r["id"].get<std::string>()] = r;
  CHECK(stored.count(owners_rule) == 1);  // the refused deletes changed nothing
  std::size_t lost = 0;
  std::map<std::string, int> uses;  // head -> stored uses of its rules
  for (const auto& [id, head] : ledger.rule_head) {
    if (stored.count(id) == 0) {
      ++lost;
      continue;
    }
    uses[head] += stored[id]["uses"].get<int>();
  }
  CHECK(ledger.rule_head.size() >= static_cast<std::size_t>(kClients * kDefines));
  CHECK(lost == 0);
  CHECK(uses == ledger.accepts);  // every acknowledged accept's counter, once
}

TEST_CASE("group commit: the kernels' writes share the WAL syncs of one server") {
  const std::string dir = fresh_dir("group-commit-count");
  Ledger ledger;
  StudioServer server(dir, {"serve.threads=16", "serve.kernels=4"});
  run_crowd(server, ledger);
  INFO("first error: " << ledger.first_error);
  CHECK(ledger.errors == 0);
  CHECK(server.stop() == 0);
  const std::string out = server.rest_of_output();
  std::smatch m;
  REQUIRE(
      std::regex_search(out, m, std::regex("lexicon group commit: (\\d+) writes, (\\d+) syncs")));
  const long writes = std::stol(m[1]), syncs = std::stol(m[2]);
  // The store's creation, the owner's define and every client's defines and accepts waited for
  // a shared sync (a refused delete rolls back: no commit). With 4 kernels answering at once,
  // commits made during a sync share the next one (measured: 48-57 syncs for these 82 writes).
  CHECK(writes == 2 + 2 * kClients * kDefines);
  CHECK(syncs >= 1);
  CHECK(syncs < writes);
}

}  // namespace flipper::studiotest::group_commit
