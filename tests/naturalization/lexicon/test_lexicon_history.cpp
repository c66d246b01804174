// The lexicon's history in the store (docs/naturalization.md §5 "History and governance"): one
// entry per change in the change's own transaction, append-only, tags, rules at a point, reverts
// that keep creation order, and the in-place upgrade of a schema 4 store. Checked with raw SQL
// where the module's own reading would hide a fault.
#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"
#include "thrown_code.hpp"

namespace fs = std::filesystem;
using flipper::naturalization::HistoryEntry;
using flipper::naturalization::LexiconStore;
using flipper::naturalization::StoredRule;

using flipper::testsupport::thrown_code;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("flipper-history-" + name + "-" + std::to_string(std::random_device{}()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

StoredRule rule(const std::string& author, const std::string& word) {
  StoredRule r;
  r.lhs = "$Action";
  r.rhs = {word, "$Number"};
  r.semantics = "{repeat $1 times {pick item }}";
  r.author = author;
  r.head = word + " 3";
  r.body = {"repeat 3 times pick item"};
  r.how = "simple";
  return r;
}

std::vector<std::string> ids(const std::vector<StoredRule>& rules) {
  std::vector<std::string> out;
  for (const auto& r : rules) out.push_back(r.id);
  return out;
}

std::vector<std::string> words(const std::vector<StoredRule>& rules) {
  std::vector<std::string> out;
  for (const auto& r : rules) out.push_back(r.rhs.at(0));
  return out;
}

std::string summary(const HistoryEntry& e) {
  return std::to_string(e.seq) + " " + e.action + " " + e.effect + " " + e.rule + " " + e.author;
}

std::vector<std::string> summaries(const std::vector<HistoryEntry>& entries) {
  std::vector<std::string> out;
  for (const auto& e : entries) out.push_back(summary(e));
  return out;
}

}  // namespace

TEST_CASE("every change is one history entry, in commit order, in the change's transaction",
          "[lexicon][history]") {
  LexiconStore store(":memory:");
  store.commit_definition({0, "glorp 3", {"b"}, "ana", 100, {}, "study-a", {}},
                          {rule("ana", "glorp"), rule("ana", "glorq")});
  store.commit_definition({0, "zed 3", {"b"}, "bob", 90}, {rule("bob", "zed")});  // clock behind
  CHECK(store.delete_rule("r1", "ana", 120, {}).status ==
        flipper::naturalization::DeleteStatus::deleted);
  // A refused delete changes nothing and records nothing.
  CHECK(store.delete_rule("r3", "ana", 130, [](const std::string&) { return true; }).status ==
        flipper::naturalization::DeleteStatus::forbidden);
  const auto all = store.history();
  CHECK(summaries(all) == std::vector<std::string>{"1 define none  ana", "2 induce add r1 ana",
                                                   "3 induce add r2 ana", "4 define none  bob",
                                                   "5 induce add r3 bob",
                                                   "6 delete remove r1 ana"});
  CHECK(all[0].head == "glorp 3");
  CHECK(all[0].body == std::vector<std::string>{"b"});
  CHECK(all[1].study == "study-a");
  CHECK(all[1].definition == 1);
  // Times never go back along the history: bob's clock said 90, after ana's 100.
  CHECK(all[3].time == 100);
  CHECK(all[5].time == 120);
  CHECK(summaries(store.history({std::string("r1"), std::nullopt})) ==
        std::vector<std::string>{"2 induce add r1 ana", "6 delete remove r1 ana"});
  CHECK(store.history({std::nullopt, std::string("bob")}).size() == 2);
  CHECK(store.history_head() == 6);
  CHECK(store.history_at_time(99) == 0);
  CHECK(store.history_at_time(100) == 5);
  CHECK(store.history_at_time(120) == 6);
}

TEST_CASE("the history is append-only and tags never move", "[lexicon][history]") {
  const fs::path dir = fresh_dir("append-only");
  const std::string path = (dir / "lexicon.db").string();
  {
    LexiconStore store(path);
    store.commit_definition({0, "glorp 3", {"b"}, "ana", 1}, {rule("ana", "glorp")});
    store.tag("first", "lead", 5);
    CHECK(thrown_code([&] { store.tag("first", "lead", 6); }) == "bad_request");
    CHECK(thrown_code([&] { store.tag("2026-11-29", "lead", 6); }) == "bad_request");
    CHECK(thrown_code([&] { store.tag("", "lead", 6); }) == "bad_request");
    CHECK(thrown_code([&] { store.tag("a b", "lead", 6); }) == "bad_request");
  }
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
  for (const char* sql : {"UPDATE lexicon_history SET author = 'mallory'",
                          "DELETE FROM lexicon_history WHERE seq = 1",
                          "UPDATE lexicon_tags SET seq = 0", "DELETE FROM lexicon_tags"}) {
    INFO(sql);
    CHECK(sqlite3_exec(db, sql, nullptr, nullptr, nullptr) == SQLITE_CONSTRAINT);
  }
  sqlite3_close(db);
  LexiconStore store(path);
  CHECK(store.history().size() == 2);
  CHECK(store.history()[0].author == "ana");
  REQUIRE(store.tags().size() == 1);
  CHECK(store.tags()[0].seq == 2);
  fs::remove_all(dir);
}

TEST_CASE("a revert makes the live rules those of the tag, in their creation order",
          "[lexicon][history]") {
  LexiconStore store(":memory:");
  store.commit_definition({0, "a 3", {"b"}, "ana", 1}, {rule("ana", "a")});  // r1
  store.commit_definition({0, "b 3", {"b"}, "bob", 2}, {rule("bob", "b")});  // r2
  store.commit_definition({0, "c 3", {"b"}, "ana", 3}, {rule("ana", "c")});  // r3
  const auto tagged = store.tag("t1", "lead", 4);
  CHECK(tagged.seq == 6);
  CHECK(tagged.checksum == flipper::naturalization::lexicon_checksum(store.rules()));
  // After the tag: the first rule deleted, one added.
  store.delete_rule("r1", "ana", 5, {});
  store.commit_definition({0, "d 3", {"b"}, "cy", 6}, {rule("cy", "d")});  // r4
  CHECK(words(store.rules()) == std::vector<std::string>{"b", "c", "d"});
  CHECK(words(store.rules_at(tagged.seq)) == std::vector<std::string>{"a", "b", "c"});
  const std::size_t entries_before = store.history().size();

  const auto out = store.revert_to(tagged.seq, {"lead", {}, "revert to t1"}, 7);
  // Nothing shared a prefix (r1 went first): every live rule goes, the three come back in order.
  CHECK(out.removed == std::vector<std::string>{"r2", "r3", "r4"});
  REQUIRE(out.restored.size() == 3);
  CHECK(out.restored[0] == std::make_pair(std::string("r5"), std::string("r1")));
  CHECK(out.restored[2] == std::make_pair(std::string("r7"), std::string("r3")));
  CHECK(words(store.rules()) == std::vector<std::string>{"a", "b", "c"});
  CHECK(ids(store.rules()) == std::vector<std::string>{"r5", "r6", "r7"});
  // The copies keep their authors; the entries name the reverter and the rule copied.
  CHECK(store.rules()[1].author == "bob");
  CHECK(flipper::naturalization::lexicon_checksum(store.rules()) == tagged.checksum);
  const auto all = store.history();
  CHECK(all.size() == entries_before + 6);  // nothing erased: six entries added
  CHECK(all.back().action == "revert");
  CHECK(all.back().author == "lead");
  CHECK(all.back().source_rule == "r3");
  CHECK(all.back().note == "revert to t1");
  CHECK(summaries(store.history({std::string("r1"), std::nullopt})) ==
        std::vector<std::string>{"2 induce add r1 ana", "7 delete remove r1 ana",
                                 std::to_string(entries_before + 4) + " revert add r5 lead"});
  // Reverting to where it is changes nothing.
  const auto again = store.revert_to(store.history_head(), {"lead", {}, ""}, 8);
  CHECK(again.removed.empty());
  CHECK(again.restored.empty());
  // A revert that keeps a prefix: to the point right after r1 and r2 were defined.
  const auto kept = store.revert_to(4, {"lead", {}, ""}, 9);
  CHECK(kept.removed == std::vector<std::string>{"r7"});
  CHECK(kept.restored.empty());
  CHECK(words(store.rules()) == std::vector<std::string>{"a", "b"});
  CHECK(thrown_code([&] {
          store.revert_to(store.history_head() + 1, {"lead", {}, ""}, 9);
        }) == "bad_request");
}

TEST_CASE("a schema 4 store is upgraded in place with a synthesized history",
          "[lexicon][history]") {
  const fs::path dir = fresh_dir("v4");
  const std::string path = (dir / "lexicon.db").string();
  {
    LexiconStore store(path);  // then taken back to version 4, as an older build left it
    store.commit_definition({0, "h", {"b"}, "ana", 10}, {rule("ana", "x"), rule("ana", "y")});
    store.commit_definition({0, "h2", {"b"}, "bob", 20}, {rule("bob", "z")});
    store.delete_rule("r2", "ana", 30, {});
  }
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
  REQUIRE(sqlite3_exec(db,
                       "DROP TRIGGER lexicon_history_append_only_d; DROP TABLE lexicon_history; "
                       "DROP TABLE lexicon_tags; UPDATE flipper_schema SET version = 4",
                       nullptr, nullptr, nullptr) == SQLITE_OK);
  sqlite3_close(db);
  LexiconStore store(path);
  const auto all = store.history();
  CHECK(summaries(all) == std::vector<std::string>{"1 import add r1 ana", "2 import add r2 ana",
                                                   "3 import add r3 bob",
                                                   "4 delete remove r2 ana"});
  CHECK(all[0].time == 10);
  CHECK(all[2].time == 20);
  CHECK(all[3].time == 30);
  CHECK(all[0].note == "synthesized at the upgrade to schema 5");
  CHECK(ids(store.rules_at(3)) == std::vector<std::string>{"r1", "r2", "r3"});
  CHECK(ids(store.rules_at(4)) == ids(store.rules()));
  // History continues after the synthesized entries.
  store.commit_definition({0, "h3", {"b"}, "cy", 40}, {rule("cy", "w")});
  CHECK(summary(store.history().back()) == "6 induce add r4 cy");
  fs::remove_all(dir);
}

TEST_CASE("a verbatim import records each rule it copies, deleted ones too", "[lexicon][history]") {
  LexiconStore from(":memory:");
  from.commit_definition({0, "h", {"b"}, "ana", 10}, {rule("ana", "x"), rule("ana", "y")});
  from.delete_rule("r1", "ana", 30, {});
  std::stringstream copy;
  from.export_jsonl(copy);
  LexiconStore to(":memory:");
  to.import_jsonl(copy);
  CHECK(summaries(to.history()) ==
        std::vector<std::string>{"1 import none  ana", "2 import add r1 ana",
                                 "3 import remove r1 ana", "4 import add r2 ana"});
  CHECK(ids(to.rules_at(to.history_head())) == std::vector<std::string>{"r2"});
}
