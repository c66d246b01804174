// The lexicon's history on a store written by 20 concurrent `flipper session` processes
// (tests/support/crowd.hpp; docs/naturalization.md §5 "History and governance"): exactly one entry
// per change, in commit order (checked with raw SQL against the rule rows), `flipper lexicon
// log/diff/tag/revert`, and a revert that restores exactly the answers of the tagged state, in a
// process that ran throughout and in a fresh one.
#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cli_test_support.hpp"
#include "crowd.hpp"
#include "session_fixture.hpp"

namespace {
using Json = nlohmann::json;
const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";

/// Rows of one SQL query, each column as text ("" for NULL).
std::vector<std::vector<std::string>> sql_rows(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr) == SQLITE_OK);
  std::vector<std::vector<std::string>> rows;
  while (sqlite3_step(st) == SQLITE_ROW) {
    std::vector<std::string> row;
    for (int i = 0; i < sqlite3_column_count(st); ++i) {
      const auto* t = sqlite3_column_text(st, i);
      row.emplace_back(t ? reinterpret_cast<const char*>(t) : "");
    }
    rows.push_back(std::move(row));
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return rows;
}

std::vector<std::string> column(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::string> out;
  for (const auto& r : rows) out.push_back(r.at(0));
  return out;
}

/// A `flipper session` on the store, as `user`.
struct Session {
  flipper::testsupport::ChildProcess child;
  Session(const std::string& store, const std::string& user)
      : child({kFlipper, "session", "--set", "lexicon.path=" + store, "-"}) {
    REQUIRE(ask({{"op", "user"}, {"name", user}}).value("ok", false));
  }
  Json ask(const Json& request) {
    REQUIRE(child.write_line(request.dump()));
    const std::string line = child.read_line(std::chrono::seconds(120));
    REQUIRE(!line.empty());
    return Json::parse(line);
  }
  /// What a user sees of a query: status, how many readings, and each shown reading's formula
  /// and authors (not scores or rule ids: a revert re-creates rules under new ids).
  std::string answer(const std::string& text) {
    const Json a = ask({{"op", "query"}, {"text", text}});
    std::string out = a.value("status", "?") + " total=" + std::to_string(a.value("total", -1));
    for (const auto& c : a["candidates"]) {
      out += " | " + c.value("formula", std::string());
      for (const auto& au : c["authors"]) out += " @" + au.get<std::string>();
    }
    return out;
  }
  std::vector<std::string> answers(const std::vector<std::string>& queries) {
    std::vector<std::string> out;
    for (const auto& q : queries) out.push_back(q + " -> " + answer(q));
    return out;
  }
  void finish() { CHECK(child.finish() == 0); }
};

flipper::clitest::Run lexicon(const std::string& store, const std::string& args) {
  return flipper::clitest::run_flipper("lexicon " + args + " --set lexicon.path=" + store, false);
}

}  // namespace

TEST_CASE("history, tag, diff and revert on a store 20 concurrent processes wrote",
          "[naturalize][process][history][crowd]") {
  flipper::testsupport::CrowdOptions o;
  o.flipper = kFlipper;
  o.store = flipper::testsupport::scratch_path("history-crowd") + ".sqlite";
  o.users = 20;
  o.defines = 3;
  const auto r = flipper::testsupport::run_crowd(o);
  for (const auto& e : r.error_samples) UNSCOPED_INFO(e);
  REQUIRE(r.errors == 0);
  REQUIRE(r.acknowledged_defines == 60);
  REQUIRE(r.acknowledged_rules == 60);
  REQUIRE(r.lost == 0);

  // ---- exactly one entry per change, in commit order (raw SQL, not the module) ----
  const auto& s = o.store;
  CHECK(column(sql_rows(s, "SELECT count(*) FROM lexicon_history")) ==
        std::vector<std::string>{"140"});  // 60 define + 60 induce + 20 delete (round 2 of 3)
  CHECK(column(sql_rows(s,
                        "SELECT count(*) FROM lexicon_history WHERE action = 'define' AND "
                        "definition IN (SELECT id FROM definitions)")) ==
        std::vector<std::string>{"60"});
  // Every rule has exactly one `induce` entry; the entries' order is the rules' creation order.
  CHECK(column(
            sql_rows(s, "SELECT rule FROM lexicon_history WHERE action = 'induce' ORDER BY seq")) ==
        column(sql_rows(s, "SELECT id FROM rules ORDER BY created")));
  // Every deletion exactly one `delete` entry by the rule's author, in deletion order.
  CHECK(column(sql_rows(s,
                        "SELECT h.rule || ' ' || h.author FROM lexicon_history h WHERE "
                        "h.action = 'delete' ORDER BY h.seq")) ==
        column(sql_rows(s,
                        "SELECT id || ' ' || author FROM rules WHERE deleted = 1 "
                        "ORDER BY deleted_seq")));
  CHECK(column(sql_rows(s, "SELECT count(*) FROM rules WHERE deleted = 1")) ==
        std::vector<std::string>{"20"});
  // A definition's entry comes right before its rules' (one transaction), with its author.
  CHECK(column(sql_rows(
            s,
            "SELECT count(*) FROM lexicon_history i JOIN lexicon_history d ON d.seq = i.seq - 1 "
            "JOIN rules r ON r.id = i.rule WHERE i.action = 'induce' AND d.action = 'define' AND "
            "d.definition = r.definition AND d.author = r.author AND d.head = r.head")) ==
        std::vector<std::string>{"60"});
  CHECK(column(sql_rows(s,
                        "SELECT count(*) FROM lexicon_history a JOIN lexicon_history b ON "
                        "b.seq = a.seq + 1 WHERE b.time < a.time")) ==
        std::vector<std::string>{"0"});

  // ---- flipper lexicon log ----
  {
    const auto log = lexicon(s, "log --json");
    REQUIRE(log.status == 0);
    const Json j = Json::parse(log.out);
    CHECK(j["entries"].size() == 140);
    const auto u3 = Json::parse(lexicon(s, "log --json --author u3").out);
    CHECK(u3["entries"].size() == 7);  // 3 definitions, 3 rules, 1 deletion
    const std::string deleted =
        column(sql_rows(s, "SELECT id FROM rules WHERE deleted = 1 ORDER BY created LIMIT 1"))[0];
    const auto one = Json::parse(lexicon(s, "log --json --rule " + deleted).out);
    REQUIRE(one["entries"].size() == 2);
    CHECK(one["entries"][0]["action"] == "induce");
    CHECK(one["entries"][1]["action"] == "delete");
  }

  // ---- the queries: every head, and the ones defined after the tag ----
  std::vector<std::string> queries =
      column(sql_rows(s, "SELECT DISTINCT head FROM definitions ORDER BY id"));
  const std::string shared_head = column(sql_rows(
      s, "SELECT head FROM rules WHERE author = 'u1' AND deleted = 0 ORDER BY created LIMIT 1"))[0];
  for (const char* q : {"glorbex up", "glorbey up", "move left", "move up thrice"})
    queries.emplace_back(q);

  Session watcher(s, "watcher");  // runs throughout: picks up the tag's state after the revert
  const auto before = watcher.answers(queries);
  REQUIRE(lexicon(s, "tag t1 --user lead").status == 0);
  const auto tagged_sum = Json::parse(lexicon(s, "log --json").out)["tags"][0]["checksum"];

  // ---- more changes after the tag: new heads, a second reading for u1's head, a deletion ----
  {
    Session u0(s, "u0");
    for (const char* h : {"glorbex up", "glorbey up"})
      REQUIRE(u0.ask({{"op", "define"}, {"head", h}, {"body", {"move up"}}}).value("ok", false));
    REQUIRE(u0.ask({{"op", "define"}, {"head", shared_head}, {"body", {"move right"}}})
                .value("ok", false));
    u0.finish();
    Session u2(s, "u2");
    const std::string mine = column(sql_rows(
        s, "SELECT id FROM rules WHERE author = 'u2' AND deleted = 0 ORDER BY created LIMIT 1"))[0];
    REQUIRE(u2.ask({{"op", "delete_rule"}, {"rule", mine}}).value("ok", false));
    u2.finish();
  }
  const auto after = watcher.answers(queries);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < before.size(); ++i) changed += before[i] != after[i] ? 1 : 0;
  CHECK(changed == 4);  // two new heads, the second reading, the deleted rule's head
  {
    const auto diff = Json::parse(lexicon(s, "diff t1 now --json").out);
    CHECK(diff["added"].size() == 3);
    CHECK(diff["removed"].size() == 1);
  }
  const auto entries_before_revert = Json::parse(lexicon(s, "log --json").out)["entries"];

  // ---- revert: the answers of the tagged state, exactly ----
  const auto rev = lexicon(s, "revert t1 --user lead");
  INFO(rev.out);
  REQUIRE(rev.status == 0);
  CHECK(watcher.answers(queries) == before);
  {
    Session fresh(s, "someone");
    CHECK(fresh.answers(queries) == before);
    fresh.finish();
  }
  watcher.finish();
  const auto diff = Json::parse(lexicon(s, "diff t1 now --json").out);
  CHECK(diff["added"].empty());
  CHECK(diff["removed"].empty());
  CHECK(diff["to"]["checksum"] == tagged_sum);
  // Nothing erased: the history before the revert is a prefix of the history after it.
  const auto entries = Json::parse(lexicon(s, "log --json").out)["entries"];
  REQUIRE(entries.size() > entries_before_revert.size());
  for (std::size_t i = 0; i < entries_before_revert.size(); ++i)
    CHECK(entries[i] == entries_before_revert[i]);
  for (std::size_t i = entries_before_revert.size(); i < entries.size(); ++i) {
    CHECK(entries[i]["action"] == "revert");
    CHECK(entries[i]["author"] == "lead");
  }
  // Unknown points are refused as misuse, naming what was given.
  const auto bad = lexicon(s, "revert no-such-tag");
  CHECK(bad.status == 2);
}
