// Moderation across sites (docs/ros2.md "Moderation across sites"; lexicon_replicator.hpp): real
// `flipper session` sites on one DDS domain of their own, the moderator's decisions made with
// `flipper lexicon approve|reject` in another process on the site's store, as a researcher does.
//   - a site with lexicon.moderation = hold_new publishes a held definition only when approved,
//     as its own event (author and world kept); a rejected one never leaves it;
//   - a site with hold_new holds what other sites define for its own moderator, and an approved
//     one is not published again;
//   - a deletion of a definition still held waits for the moderator's decision.
// Every "never arrives" is checked behind a barrier: a later event of the same writer (delivered
// in order) that did arrive.
#include <sqlite3.h>

#include <map>
#include <set>

#include "dds_test_support.hpp"
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/msg/LexiconEvent.h"
#include "sqlite_integrity.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

const std::vector<std::string> kHoldNew = {"--set", "lexicon.moderation=hold_new"};

json define(Site& site, const std::string& head, const std::string& body) {
  return site.call({{"op", "define"}, {"head", head}, {"body", {body}}});
}

/// `flipper lexicon VERB ARGS... --set lexicon.path=STORE` (the moderator's process).
CommandRun lexicon(const Site& site, std::vector<std::string> args) {
  args.insert(args.begin(), {flipper_bin(), "lexicon"});
  args.insert(args.end(),
              {"--set", "lexicon.path=" + site.store, "--set", "lexicon.site=" + site.name});
  return run_command(args);
}

json pending(const Site& site) {
  const CommandRun r = lexicon(site, {"pending", "--json"});
  REQUIRE(r.status == 0);
  return json::parse(r.out)["pending"];
}

/// The history entries of a site's store with `action`.
std::vector<json> history(const Site& site, const std::string& action) {
  const CommandRun r = lexicon(site, {"log", "--json"});
  REQUIRE(r.status == 0);
  const json log = json::parse(r.out);
  std::vector<json> out;
  for (const auto& e : log["entries"])
    if (e["action"] == action) out.push_back(e);
  return out;
}

/// A replication log row's status in a site's store ("" when there is none).
std::string log_status(const Site& site, const std::string& origin, int version) {
  sqlite3* db = nullptr;
  std::string status;
  if (sqlite3_open_v2(site.store.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT status FROM dds_replication WHERE site = ? AND version = ?",
                           -1, &st, nullptr) == SQLITE_OK) {
      sqlite3_bind_text(st, 1, origin.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int(st, 2, version);
      if (sqlite3_step(st) == SQLITE_ROW)
        status = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
      sqlite3_finalize(st);
    }
  }
  sqlite3_close(db);
  return status;
}

/// What a test participant has seen on the lexicon topic, by (site, version) (relays merged).
struct SeenEvents {
  struct Event {
    std::string kind, head, author;
    bool has_world = false;
  };
  std::map<std::pair<std::string, std::uint64_t>, Event> by_key;
  SampleReader<flipper_msg_dds__LexiconEvent_> reader;
  explicit SeenEvents(dds::Participant& p)
      : reader(p, &flipper_msg_dds__LexiconEvent__desc, dds::kLexiconTopic) {}
  void take() {
    reader.take([&](const flipper_msg_dds__LexiconEvent_& s) {
      by_key[{s.site_, s.version_}] = {s.kind_, s.head_, s.author_, s.world_[0] != '\0'};
    });
  }
  /// The heads of `site`'s definitions seen, by version.
  std::map<std::uint64_t, std::string> heads(const std::string& site) {
    take();
    std::map<std::uint64_t, std::string> out;
    for (const auto& [key, e] : by_key)
      if (key.first == site && e.kind == "define") out[key.second] = e.head;
    return out;
  }
};

}  // namespace

TEST_CASE("a held definition leaves its site only when approved, as the site's own event",
          "[dds][moderation]") {
  const auto dir = scratch_dir("moderation-publish");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain, kHoldNew), b("b", dir, kDomain);
  auto participant = test_participant(kDomain);
  SeenEvents seen(*participant);
  for (Site* s : {&a, &b}) s->call({{"op", "user"}, {"name", "ana"}});

  REQUIRE(define(a, "pick 3 items", "repeat 3 times pick item")["held"] == "h1");
  REQUIRE(define(a, "go home", "visit room1")["held"] == "h2");
  CHECK(a.top("drop 2 items") == "");  // held: serves no one, its author included
  CHECK(a.top("go home") == "");

  // rita approves h2 (another process on a's store): a publishes it, b applies it.
  const CommandRun ok = lexicon(a, {"approve", "h2", "--user", "rita"});
  INFO(ok.out);
  REQUIRE(ok.status == 0);
  CHECK(wait_until([&] { return b.top("go home") == "{visit room1}"; }));
  CHECK(a.top("go home") == "{visit room1}");
  CHECK(wait_until([&] { return !seen.heads("a").empty(); }));
  // On the wire: one event of a, version 1, the approved definition, by its author, with the
  // world it was defined in. h1, held before it from the same writer, was never published.
  CHECK(seen.heads("a") == std::map<std::uint64_t, std::string>{{1, "go home"}});
  CHECK(seen.by_key[{"a", 1}].author == "ana");
  CHECK(seen.by_key[{"a", 1}].has_world);
  CHECK(b.top("drop 2 items") == "");
  for (const auto& r : b.rules()) CHECK(r["author"] == "ana");

  // rita rejects h1; then a definition approved after it is the barrier: h1 never leaves a.
  REQUIRE(lexicon(a, {"reject", "h1", "--user", "rita", "--reason", "too vague"}).status == 0);
  REQUIRE(define(a, "go away", "visit room2")["held"] == "h3");
  REQUIRE(lexicon(a, {"approve", "h3", "--user", "rita"}).status == 0);
  CHECK(wait_until([&] { return b.top("go away") == "{visit room2}"; }));
  CHECK(wait_until([&] { return seen.heads("a").size() == 2; }));
  CHECK(seen.heads("a") == std::map<std::uint64_t, std::string>{{1, "go home"}, {2, "go away"}});
  CHECK(b.top("drop 2 items") == "");
  CHECK(a.top("drop 2 items") == "");

  // The moderator is in a's history (approvals and the rejection, with its reason); the
  // rejection is a's alone, and b's history has the definitions by their author.
  const auto approvals = history(a, "approve");
  REQUIRE(approvals.size() == 2);
  CHECK(approvals[0]["author"] == "rita");
  CHECK(approvals[0]["note"] == "h2");
  const auto rejections = history(a, "reject");
  REQUIRE(rejections.size() == 1);
  CHECK(rejections[0]["author"] == "rita");
  CHECK(rejections[0]["note"] == "h1: too vague");
  CHECK(history(b, "reject").empty());
  CHECK(history(b, "hold").empty());
  std::set<std::string> b_heads;
  for (const auto& e : history(b, "replicate")) {
    CHECK(e["author"] == "ana");
    b_heads.insert(e["head"].get<std::string>());
  }
  CHECK(b_heads == std::set<std::string>{"go home", "go away"});

  for (Site* s : {&a, &b}) CHECK(s->child->finish() == 0);
  for (Site* s : {&a, &b}) CHECK(testsupport::sqlite_integrity(s->store) == "ok");
  std::filesystem::remove_all(dir);
}

TEST_CASE("a site with hold_new holds other sites' definitions for its own moderator",
          "[dds][moderation]") {
  const auto dir = scratch_dir("moderation-hold");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain), b("b", dir, kDomain, kHoldNew);
  for (Site* s : {&a, &b}) s->call({{"op", "user"}, {"name", "ana"}});

  REQUIRE(define(a, "go home", "visit room1")["ok"] == true);
  REQUIRE(define(a, "wander off", "move down")["ok"] == true);
  CHECK(a.top("go home") == "{visit room1}");
  // b holds both, in the order they were made, for its moderator.
  REQUIRE(wait_until([&] { return pending(b).size() == 2; }));
  const json held = pending(b);
  CHECK(held[0]["id"] == "h1");
  CHECK(held[0]["head"] == "go home");
  CHECK(held[0]["author"] == "ana");
  CHECK(held[0]["via"] == "replicate");
  CHECK(held[1]["id"] == "h2");
  CHECK(held[1]["head"] == "wander off");
  CHECK(b.top("go home") == "");
  CHECK(b.top("wander off") == "");

  // bob approves h1 at b: it serves at b. He rejects h2: it never does.
  REQUIRE(lexicon(b, {"approve", "h1", "--user", "bob"}).status == 0);
  CHECK(wait_until([&] { return b.top("go home") == "{visit room1}"; }));
  REQUIRE(lexicon(b, {"reject", "h2", "--user", "bob"}).status == 0);
  // The barrier: b's own definition, approved and published after both decisions.
  REQUIRE(define(b, "go away", "visit room2")["held"] == "h3");
  REQUIRE(lexicon(b, {"approve", "h3", "--user", "bob"}).status == 0);
  CHECK(wait_until([&] { return a.top("go away") == "{visit room2}"; }));
  CHECK(b.top("wander off") == "");
  CHECK(b.top("go away") == "{visit room2}");
  CHECK(log_status(b, "a", 1) == "applied");
  CHECK(log_status(b, "a", 2) == "rejected");
  // a's definitions are a's events: b's approval published none of them again.
  CHECK(definitions_per_head(a.store) ==
        std::map<std::string, int>{{"go home", 1}, {"wander off", 1}, {"go away", 1}});
  CHECK(a.top("go home") == "{visit room1}");
  CHECK(a.top("wander off") == "{move down}");  // b's rejection is b's alone

  for (Site* s : {&a, &b}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("a deletion of a definition still held waits for the moderator's decision",
          "[dds][moderation]") {
  const auto dir = scratch_dir("moderation-delete");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain), b("b", dir, kDomain, kHoldNew);
  for (Site* s : {&a, &b}) s->call({{"op", "user"}, {"name", "ana"}});

  REQUIRE(define(a, "spin round", "move left")["ok"] == true);
  REQUIRE(wait_until([&] { return pending(b).size() == 1; }));
  for (const auto& r : a.rules())
    REQUIRE(a.call({{"op", "delete_rule"}, {"rule", r["id"]}})["ok"] == true);
  // The deletion (a#2) reaches b and waits there: its definition is held.
  REQUIRE(wait_until([&] { return log_status(b, "a", 2) == "pending"; }));
  CHECK(log_status(b, "a", 1) == "held");

  // Approved after its author deleted it: it serves at b not even for a moment past the
  // decision (the deletion applies with it).
  REQUIRE(lexicon(b, {"approve", "h1", "--user", "bob"}).status == 0);
  CHECK(wait_until([&] { return log_status(b, "a", 2) == "applied"; }));
  CHECK(log_status(b, "a", 1) == "applied");
  CHECK(b.top("spin round") == "");
  CHECK(b.rules().empty());

  for (Site* s : {&a, &b}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("decisions made while a site was down are followed when it starts again",
          "[dds][moderation]") {
  const auto dir = scratch_dir("moderation-restart");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain), b("b", dir, kDomain, kHoldNew);
  auto participant = test_participant(kDomain);
  SeenEvents seen(*participant);
  for (Site* s : {&a, &b}) s->call({{"op", "user"}, {"name", "ana"}});
  REQUIRE(define(a, "go home", "visit room1")["ok"] == true);
  REQUIRE(wait_until([&] { return pending(b).size() == 1; }));
  REQUIRE(define(b, "go away", "visit room2")["held"] == "h2");
  CHECK(b.child->finish() == 0);

  // bob approves both while b is down.
  REQUIRE(lexicon(b, {"approve", "h1", "--user", "bob"}).status == 0);
  REQUIRE(lexicon(b, {"approve", "h2", "--user", "bob"}).status == 0);
  b.start();
  b.call({{"op", "user"}, {"name", "ana"}});
  // b's own approved definition is published at start-up as b#1, with its world; a's is not
  // published again (it is a's event): a keeps one definition of it.
  CHECK(wait_until([&] { return a.top("go away") == "{visit room2}"; }));
  CHECK(b.top("go home") == "{visit room1}");
  CHECK(wait_until([&] { return !seen.heads("b").empty(); }));
  CHECK(seen.heads("b") == std::map<std::uint64_t, std::string>{{1, "go away"}});
  CHECK(seen.by_key[{"b", 1}].has_world);
  CHECK(definitions_per_head(a.store) ==
        std::map<std::string, int>{{"go home", 1}, {"go away", 1}});

  for (Site* s : {&a, &b}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("with DDS Security an approved definition is signed by its site and accepted",
          "[dds][moderation][security]") {
  const auto dir = scratch_dir("moderation-secured");
  const std::string ks = (dir / "ks").string();
  const int kDomain = test_domain();
  REQUIRE(security_command({"init", ks}).status == 0);
  for (const char* name : {"lab1", "lab2"})
    REQUIRE(security_command({"add", ks, name}).status == 0);
  std::vector<std::string> held = {"--set", "dds.security.keystore=" + ks};
  const std::vector<std::string> secure = held;
  held.insert(held.end(), kHoldNew.begin(), kHoldNew.end());
  Site lab1("lab1", dir, kDomain, held), lab2("lab2", dir, kDomain, secure);
  for (Site* s : {&lab1, &lab2}) s->call({{"op", "user"}, {"name", "ana"}});
  REQUIRE(define(lab1, "go home", "visit room1")["held"] == "h1");
  REQUIRE(lexicon(lab1, {"approve", "h1", "--user", "rita"}).status == 0);
  // lab2 accepts only events signed by the site they name (event_signature.hpp).
  CHECK(
      wait_until([&] { return lab2.top("go home") == "{visit room1}"; }, std::chrono::seconds(60)));
  for (Site* s : {&lab1, &lab2}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}
