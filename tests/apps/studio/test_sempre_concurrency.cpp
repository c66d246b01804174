// /sempre under the client's concurrency (docs/sempre.md § Concurrency): :dictionary racing with
// :def and :delete, repeated dictionaries, fire-and-forget accepts overtaken by the next context
// and query. Several clients at once, each with a second connection for what it does not await.
#include <future>
#include <mutex>
#include <set>
#include <thread>

#include "sempre_client.hpp"
#include "studio_server.hpp"

namespace flipper::sempretest {
namespace {

using studiotest::fresh_dir;
using studiotest::StudioServer;

constexpr int kClients = 6;
constexpr int kAccepts = 5;
const char* const kWords[kClients] = {"alpha", "bravo", "charlie", "delta", "echo", "foxtrot"};

// Every answer of the run: each must be whole, and stats.count unique.
struct Seen {
  std::mutex mutex;
  std::vector<std::uint64_t> counts;
  int malformed = 0;
  void add(const SempreReply& r) {
    std::lock_guard lock(mutex);
    const bool whole = r.status == 200 && r.body.is_object() && r.body["stats"].is_object() &&
                       r.body["lines"].is_array() && r.body["candidates"].is_array() &&
                       r.body["stats"]["count"].is_number_unsigned();
    if (!whole) {
      ++malformed;
      return;
    }
    counts.push_back(r.body["stats"]["count"]);
  }
};

// The dictionary of an answer, or null when it is not a JSON list in a string (no Catch
// assertion here: the clients' threads call it).
json dictionary_of(const SempreReply& r) {
  if (!r.body.is_object() || !r.body["stats"]["dictionary"].is_string()) return nullptr;
  const json d = json::parse(r.body["stats"]["dictionary"].get<std::string>(), nullptr, false);
  return d.is_array() ? d : json();
}

bool lists_head(const json& dict, const std::string& head) {
  if (!dict.is_array()) return false;
  for (const auto& e : dict)
    if (e["head"] == head) return true;
  return false;
}

std::string definition(const std::string& head) {
  const std::string body = json::array({json::array({"move up", "{move up}"}),
                                        json::array({"move right", "{move right}"})})
                               .dump();
  return "(:def " + json(head).dump() + " " + json(body).dump() + ")";
}

}  // namespace

TEST_CASE("concurrent clients: definitions, dictionaries, accepts and deletions in any order") {
  StudioServer server(fresh_dir("sempre-concurrency"), {"serve.sempre=true"});
  const json map = study_map();
  Seen seen;
  std::mutex check;  // Catch's assertions are not thread-safe
  std::vector<std::string> failures;
  auto fail = [&](const std::string& what) {
    std::lock_guard lock(check);
    failures.push_back(what);
  };
  auto get = [&](httplib::Client& c, const std::string& command, const std::string& sid) {
    c.set_url_encode(false);  // sempre_target encodes as the browser does
    auto res = c.Get(sempre_target(command, sid).c_str());
    SempreReply r;
    if (!res) {
      fail("no answer to " + command);
      return r;
    }
    r.status = res->status;
    r.body = json::parse(res->body, nullptr, false);
    seen.add(r);
    return r;
  };

  // `n` dictionaries on connection `b`, not awaited: each must be a whole list, whatever it holds.
  auto race_dictionaries = [&](httplib::Client& b, const std::string& sid, int n) {
    return std::async(std::launch::async, [&, sid, n] {
      for (int k = 0; k < n; ++k) {
        const SempreReply r = get(b, "(:dictionary)", sid);
        if (dictionary_of(r).is_null()) fail("a racing dictionary is not a list: " + r.body.dump());
      }
    });
  };

  // Phase 1: each client defines while its other connection asks for the dictionary repeatedly.
  // Phase 2: it asks for its phrase and accepts it without waiting, its next context and query
  // going out at once.
  std::vector<long> indexes(kClients, -1);
  auto define_and_accept = [&](int i) {
    const std::string sid = "client" + std::to_string(i);
    const std::string head = std::string("hop ") + kWords[i];
    httplib::Client a = server.client(), b = server.client();
    auto racing = race_dictionaries(b, sid, 3);
    const SempreReply def = get(a, definition(head), sid);
    if (def.body["lines"] != json::array() ||
        def.body["candidates"][0]["formula"] != "{{move up};{move right}}")
      fail(head + ": " + def.body.dump());
    racing.get();  // answered before or after the definition, but whole
    // Asked after the definition's answer arrived: it is there.
    const json dict = dictionary_of(get(a, "(:dictionary)", sid));
    if (!lists_head(dict, head)) fail(head + " missing from " + dict.dump());
    for (const auto& e : dict)
      if (e["head"] == head) indexes[static_cast<std::size_t>(i)] = e["index"];

    std::vector<std::future<SempreReply>> accepts;
    for (int k = 0; k < kAccepts; ++k) {
      get(a, context_command(map), sid);
      const SempreReply q = get(a, query_command(head), sid);
      if (q.body["stats"]["status"] != "Induced") fail(head + ": " + q.body.dump());
      const std::string formula = q.body["candidates"][0]["formula"];
      const std::string accept = "(:accept " + json(head).dump() + " " + json(formula).dump() + ")";
      accepts.push_back(std::async(std::launch::async, [&, accept, sid] {
        httplib::Client c = server.client();
        return get(c, accept, sid);
      }));
      get(a, context_command(map), sid);
      get(a, query_command("move left"), sid);
    }
    for (auto& f : accepts)
      if (f.get().body["lines"] != json::array()) fail(head + ": an accept was refused");
  };
  // Phase 3: each client deletes its rule while its other connection asks for the dictionary.
  auto delete_own = [&](int i) {
    const std::string sid = "client" + std::to_string(i);
    const std::string head = std::string("hop ") + kWords[i];
    httplib::Client a = server.client(), b = server.client();
    auto racing = race_dictionaries(b, sid, 2);
    const SempreReply del =
        get(a, "(:delete " + std::to_string(indexes[static_cast<std::size_t>(i)]) + ")", sid);
    racing.get();
    if (del.body["lines"] != json::array()) fail(head + ": delete: " + del.body.dump());
    const json after = dictionary_of(get(a, "(:dictionary)", sid));
    if (after.is_null() || lists_head(after, head))
      fail(head + " still listed after its deletion: " + after.dump());
  };
  auto run_all = [&](const auto& work) {
    std::vector<std::thread> clients;
    for (int i = 0; i < kClients; ++i)
      clients.emplace_back([&, i] {
        try {  // a garbled answer must fail the test, not terminate it
          work(i);
        } catch (const std::exception& e) {
          fail(std::string("client ") + std::to_string(i) + ": " + e.what());
        }
      });
    for (auto& t : clients) t.join();
  };

  run_all(define_and_accept);
  INFO(failures.size() << " failures, first: " << (failures.empty() ? "" : failures[0]));
  REQUIRE(failures.empty());
  CHECK(std::set<long>(indexes.begin(), indexes.end()).size() == kClients);
  // Every accept was counted exactly once: each client's one rule has kAccepts uses by its author.
  auto http = server.client();
  const std::string session = studiotest::new_session(http);
  const studiotest::Reply listed = studiotest::post(http, session, R"({"op":"rules"})");
  REQUIRE(listed.body["rules"].size() == kClients);
  for (const auto& r : listed.body["rules"]) {
    INFO(r.dump());
    CHECK(r["uses_by_author"] == kAccepts);
    CHECK(r["uses_by_others"] == 0);
  }

  run_all(delete_own);
  CHECK(failures.empty());
  CHECK(seen.malformed == 0);
  std::set<std::uint64_t> distinct(seen.counts.begin(), seen.counts.end());
  CHECK(distinct.size() == seen.counts.size());
  CHECK(studiotest::post(http, session, R"({"op":"rules"})").body["rules"] == json::array());
  CHECK(dictionary_of(sempre_get(http, "(:dictionary)", "observer")) == json::array());
}

}  // namespace flipper::sempretest
