// One lexicon across sites (apps/dds/lexicon_replicator.hpp), with real `flipper session`
// processes on one DDS domain per test: a definition, a deletion, a refused deletion and a
// conflicting pair replicate between three sites; a site killed with SIGKILL mid-stream
// catches up after a restart with no definition lost and none duplicated; malformed events
// are dropped. Expected formulas are the core language's (docs/protocol.md example), and the
// conflict winner follows from the rule: larger (lamport, site) wins, so site "b" on a tie.
#include <csignal>
#include <set>

#include "dds_test_support.hpp"
#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/msg/LexiconEvent.h"
#include "sqlite_integrity.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

std::uint32_t matched(dds_entity_t writer) {
  dds_publication_matched_status_t st{};
  dds_get_publication_matched_status(writer, &st);
  return st.current_count;
}

}  // namespace

TEST_CASE("three sites share a definition, a deletion and a conflicting pair", "[dds]") {
  const auto dir = scratch_dir("three");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain), b("b", dir, kDomain), c("c", dir, kDomain);
  for (Site* s : {&a, &b, &c}) s->call({{"op", "user"}, {"name", "ana"}});

  // A definition at a: usable at b and c (the 1 s figure is in bench/dds).
  REQUIRE(a.call({{"op", "define"},
                  {"head", "pick 3 items"},
                  {"body", {"repeat 3 times pick item"}}})["ok"] == true);
  const std::string drop2 = "{repeat 2 times {drop item }}";
  CHECK(a.top("drop 2 items") == drop2);
  for (Site* s : {&b, &c}) CHECK(wait_until([&] { return s->top("drop 2 items") == drop2; }));
  CHECK(rule_shapes(b) == rule_shapes(a));
  CHECK(rule_shapes(c) == rule_shapes(a));

  // Only the author's site may delete: b refuses to delete its copy of a's rule.
  const json b_rule = b.rules().at(0);
  const json refused = b.call({{"op", "delete_rule"}, {"rule", b_rule["id"]}});
  CHECK(refused["error"]["code"] == "forbidden");
  CHECK(rule_shapes(b) == rule_shapes(a));

  // A deletion at a reaches b and c: every rule of the definition goes.
  for (const auto& r : a.rules())
    REQUIRE(a.call({{"op", "delete_rule"}, {"rule", r["id"]}})["ok"] == true);
  CHECK(a.rules().empty());
  for (Site* s : {&b, &c}) CHECK(wait_until([&] { return s->rules().empty(); }));
  CHECK(c.top("drop 2 items") != drop2);

  // A conflicting pair: a and b define "go home" at once. Equal clocks (both saw the same
  // history), so the larger site name, b, wins everywhere.
  REQUIRE(a.child->write_line(
      json{{"op", "define"}, {"head", "go home"}, {"body", {"visit room1"}}}.dump()));
  REQUIRE(b.child->write_line(
      json{{"op", "define"}, {"head", "go home"}, {"body", {"visit room2"}}}.dump()));
  CHECK(json::parse(a.child->read_line())["ok"] == true);
  CHECK(json::parse(b.child->read_line())["ok"] == true);
  for (Site* s : {&a, &b, &c})
    CHECK(wait_until([&] { return s->top("go home") == "{visit room2}"; }));
  const auto winner = rule_shapes(b, "go home");
  CHECK(winner.size() == 1);
  CHECK(rule_shapes(a, "go home") == winner);
  CHECK(rule_shapes(c, "go home") == winner);

  // Malformed and forged events are dropped or refused; the sites go on. One reliable writer,
  // matched by the three sites before it writes; the last event is a valid one, so once every
  // site has applied it, the three before it (delivered in order) have been read and judged.
  auto participant = test_participant(kDomain);
  const dds_entity_t w = lexicon_writer(*participant);
  REQUIRE(wait_until([&] { return matched(w) >= 3; }, std::chrono::seconds(60)));
  dds::LexiconEvent bad;
  bad.site = "mallory";
  bad.kind = "define";
  bad.author = "eve";
  bad.head = "steal";
  bad.body = {"move up"};
  write_event(w, bad);  // version 0
  bad.version = 1;
  bad.kind = "zap";
  write_event(w, bad);
  dds::LexiconEvent forged;
  forged.site = "mallory";
  forged.version = 2;
  forged.kind = "delete";
  forged.author = "eve";
  forged.target_site = "b";
  forged.target_version = 1;  // b's "go home"
  write_event(w, forged);
  dds::LexiconEvent valid = bad;  // security is off: any participant may define
  valid.version = 3;
  valid.lamport = 100;
  valid.kind = "define";
  valid.head = "wander off";
  valid.body = {"move down"};
  write_event(w, valid);
  for (Site* s : {&a, &b, &c})
    CHECK(wait_until([&] { return s->top("wander off") == "{move down}"; },
                     std::chrono::seconds(60)));
  dds_delete(w);
  for (Site* s : {&a, &b, &c}) {
    CHECK(s->top("go home") == "{visit room2}");
    CHECK(s->top("steal") == "");
  }
  for (Site* s : {&a, &b, &c}) CHECK(s->child->finish() == 0);
  for (Site* s : {&a, &b, &c}) CHECK(testsupport::sqlite_integrity(s->store) == "ok");
  std::filesystem::remove_all(dir);
}

TEST_CASE("a site that redefines a head it received keeps only its own, later definition",
          "[dds]") {
  // The interleaving the conflicting pair above only meets by chance: b has applied a's "go home"
  // before b defines it. b's definition saw a's, so it is later and wins at every site, b included.
  const auto dir = scratch_dir("redefine");
  const int kDomain = test_domain();
  Site a("a", dir, kDomain), b("b", dir, kDomain);
  for (Site* s : {&a, &b}) s->call({{"op", "user"}, {"name", "ana"}});
  REQUIRE(a.call({{"op", "define"}, {"head", "go home"}, {"body", {"visit room1"}}})["ok"] == true);
  REQUIRE(wait_until([&] { return b.top("go home") == "{visit room1}"; }));
  REQUIRE(b.call({{"op", "define"}, {"head", "go home"}, {"body", {"visit room2"}}})["ok"] == true);
  for (Site* s : {&a, &b}) CHECK(wait_until([&] { return s->top("go home") == "{visit room2}"; }));
  const std::set<std::string> own = {"$Action -> [\"go\",\"home\"] => {visit room2}"};
  CHECK(rule_shapes(b, "go home") == own);
  CHECK(wait_until([&] { return rule_shapes(a, "go home") == own; }));
  for (Site* s : {&a, &b}) CHECK(s->child->finish() == 0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("a site killed mid-stream catches up with 0 lost and 0 duplicate definitions", "[dds]") {
  const auto dir = scratch_dir("kill");
  const int kDomain = test_domain();
  const std::vector<std::string> words = {"alpha",   "bravo",  "charlie", "delta",    "echo",
                                          "foxtrot", "golf",   "hotel",   "india",    "juliet",
                                          "kilo",    "lima",   "mike",    "november", "oscar",
                                          "papa",    "quebec", "romeo",   "sierra",   "tango"};
  Site a("a", dir, kDomain), c("c", dir, kDomain);
  a.call({{"op", "user"}, {"name", "ana"}});
  const auto define = [&](std::size_t i) {
    const json r = a.call({{"op", "define"},
                           {"head", "chore " + words[i]},
                           {"body", {i % 2 ? "move left" : "move right", "move up"}}});
    REQUIRE(r["ok"] == true);
  };
  for (std::size_t i = 0; i < 7; ++i) define(i);
  // c has at least started receiving, then dies mid-stream.
  REQUIRE(wait_until([&] { return !c.top("chore alpha").empty(); }));
  for (std::size_t i = 7; i < 10; ++i) define(i);
  c.child->kill_now();
  for (std::size_t i = 10; i < words.size(); ++i) define(i);
  c.start();  // same store, same site
  for (const auto& w : words) CHECK(wait_until([&] { return !c.top("chore " + w).empty(); }));
  CHECK(rule_shapes(c) == rule_shapes(a));
  // Replays after the restart (the whole history comes again) add nothing.
  Site late("d", dir, kDomain);
  for (const auto& w : words) CHECK(wait_until([&] { return !late.top("chore " + w).empty(); }));
  CHECK(rule_shapes(late) == rule_shapes(a));
  for (Site* s : {&a, &c, &late}) CHECK(s->child->finish() == 0);
  for (Site* s : {&a, &c, &late}) {
    const auto per_head = definitions_per_head(s->store);
    CHECK(per_head.size() == words.size());
    for (const auto& [head, n] : per_head) {
      INFO(s->name << ": " << head);
      CHECK(n == 1);
    }
    CHECK(testsupport::sqlite_integrity(s->store) == "ok");
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("a late joiner catches up from a live site while the author is down", "[dds]") {
  // Start lab2, then lab1; lab1 defines 35 rules; lab1 stops; lab4 starts: lab4 must get all 35
  // from lab2, which relays what it receives (lexicon_replicator.hpp).
  const auto dir = scratch_dir("late");
  const int kDomain = test_domain();
  Site lab2("lab2", dir, kDomain);
  Site lab1("lab1", dir, kDomain);
  lab1.call({{"op", "user"}, {"name", "ana"}});
  constexpr int kRules = 35;
  const std::vector<std::string> moves = {"move left", "move right", "move up", "move down"};
  std::set<std::string> heads;
  for (int i = 0; i < kRules; ++i) {
    const std::string head = "chore number " + std::to_string(i);
    heads.insert(head);
    REQUIRE(lab1.call({{"op", "define"},
                       {"head", head},
                       {"body", {moves[static_cast<std::size_t>(i) % 4], "move up"}}})["ok"] ==
            true);
  }
  const auto heads_at = [](Site& s) {
    std::set<std::string> out;
    for (const auto& r : s.rules()) out.insert(r["head"].get<std::string>());
    return out;
  };
  REQUIRE(wait_until([&] { return heads_at(lab2) == heads; }));
  const auto expected = rule_shapes(lab1);
  CHECK(lab1.child->finish() == 0);  // the author is down from here on
  Site lab4("lab4", dir, kDomain);
  CHECK(wait_until([&] { return heads_at(lab4).size() == kRules; }, std::chrono::seconds(60)));
  CHECK(heads_at(lab4) == heads);
  CHECK(rule_shapes(lab4) == expected);
  for (Site* s : {&lab2, &lab4}) CHECK(s->child->finish() == 0);
  for (const Site* s : {&lab1, &lab2, &lab4}) {
    const auto per_head = definitions_per_head(s->store);
    CHECK(per_head.size() == static_cast<std::size_t>(kRules));
    for (const auto& [head, n] : per_head) CHECK(n == 1);
  }
  std::filesystem::remove_all(dir);
}
