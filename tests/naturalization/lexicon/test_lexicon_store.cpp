#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"

namespace fs = std::filesystem;
using flipper::naturalization::LexiconStore;
using flipper::naturalization::StoredRule;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("flipper-lexicon-" + name + "-" + std::to_string(std::random_device{}()));
  fs::remove_all(dir);
  return dir;
}

StoredRule make_rule(std::int64_t created, const std::string& author) {
  StoredRule r;
  r.created = created;
  r.id = "r" + std::to_string(created);
  r.lhs = "$Action";
  r.rhs = {"pick", "$Number", "items"};
  r.semantics = "{repeat $1 times {pick item }}";
  r.author = author;
  r.head = "pick 3 items";
  r.body = {"repeat 3 times pick item"};
  r.how = "simple";
  return r;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("store is created with parent directories and keeps definitions across reopen",
          "[lexicon]") {
  const fs::path dir = fresh_dir("reopen");
  const std::string path = (dir / "a" / "b" / "lexicon.db").string();
  {
    LexiconStore store(path);
    CHECK(store.max_created() == 0);
    const auto id =
        store.add_definition({0, "pick 3 items", {"repeat 3 times pick item"}, "ana", 7},
                             {make_rule(1, "ana"), make_rule(2, "ana")});
    CHECK(id == 1);
  }
  REQUIRE(fs::exists(path));
  LexiconStore store(path);
  const auto defs = store.definitions();
  REQUIRE(defs.size() == 1);
  CHECK(defs[0].head == "pick 3 items");
  CHECK(defs[0].body == std::vector<std::string>{"repeat 3 times pick item"});
  CHECK(defs[0].author == "ana");
  const auto rules = store.rules();
  REQUIRE(rules.size() == 2);
  CHECK(rules[0].id == "r1");
  CHECK(rules[0].rhs == std::vector<std::string>{"pick", "$Number", "items"});
  CHECK(rules[0].semantics == "{repeat $1 times {pick item }}");
  CHECK(rules[0].definition == 1);
  CHECK(store.max_created() == 2);
  fs::remove_all(dir);
}

TEST_CASE("the store file is in WAL mode with a schema version", "[lexicon]") {
  const fs::path dir = fresh_dir("wal");
  const std::string path = (dir / "lexicon.db").string();
  { LexiconStore store(path); }
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  CHECK(std::string(reinterpret_cast<const char*>(sqlite3_column_text(st, 0))) == "wal");
  sqlite3_finalize(st);
  REQUIRE(sqlite3_prepare_v2(db, "SELECT version FROM flipper_schema", -1, &st, nullptr) ==
          SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  CHECK(sqlite3_column_int(st, 0) == LexiconStore::kSchemaVersion);
  sqlite3_finalize(st);
  sqlite3_close(db);
  fs::remove_all(dir);
}

TEST_CASE("deleting a rule keeps its history", "[lexicon]") {
  LexiconStore store(":memory:");
  store.add_definition({0, "h", {"b"}, "ana", 1}, {make_rule(1, "ana"), make_rule(2, "ana")});
  CHECK(store.mark_deleted("r1", 99));
  CHECK_FALSE(store.mark_deleted("r1", 100));  // already deleted
  CHECK_FALSE(store.mark_deleted("nope", 100));
  const auto live = store.rules();
  REQUIRE(live.size() == 1);
  CHECK(live[0].id == "r2");
  const auto all = store.rules(true);
  REQUIRE(all.size() == 2);
  CHECK(all[0].deleted);
  CHECK(all[0].deleted_at == 99);
  CHECK(store.rule("r1")->deleted);
  CHECK_FALSE(store.rule("missing"));
}

TEST_CASE("accepts persist use counters and weights together", "[lexicon]") {
  LexiconStore store(":memory:");
  store.add_definition({0, "h", {"b"}, "ana", 1}, {make_rule(1, "ana")});
  CHECK_FALSE(store.load_weights("global"));
  store.record_accept({{"r1", 2, 5}}, "global", "w=1");
  CHECK(store.load_weights("global") == std::optional<std::string>("w=1"));
  const auto r = store.rule("r1");
  CHECK(r->uses_by_author == 2);
  CHECK(r->uses_by_others == 5);
  store.save_weights("user:bob", "w=2");
  CHECK(*store.load_weights("user:bob") == "w=2");
  CHECK(*store.load_weights("global") == "w=1");
}

namespace {
std::int64_t counter_rows(const std::string& path) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "SELECT count(*) FROM rule_uses", -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  const std::int64_t n = sqlite3_column_int64(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  return n;
}
}  // namespace

TEST_CASE("a rule gets its counter row at its first use, not when it is stored", "[lexicon]") {
  const fs::path dir = fresh_dir("uses");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore store(path);
  store.add_definition({0, "h", {"b"}, "ana", 1}, {make_rule(1, "ana"), make_rule(2, "ana")});
  CHECK(counter_rows(path) == 0);
  CHECK(store.rule("r1")->uses_by_author == 0);
  CHECK(store.rule("r1")->uses_by_others == 0);
  store.record_accept({{"r1", 1, 0}}, "global", "w=1");
  CHECK(counter_rows(path) == 1);
  CHECK(store.rule("r1")->uses_by_author == 1);
  CHECK(store.rule("r2")->uses_by_author == 0);
  // A rule imported with its counters keeps them.
  std::stringstream line;
  line << R"({"type":"rule","id":"r3","lhs":"$Action","rhs":["x"],"semantics":"{pick item }",)"
       << R"("author":"bob","how":"simple","created":3,"uses_by_others":4})"
       << "\n";
  CHECK(store.import_jsonl(line) == 1);
  CHECK(counter_rows(path) == 2);
  CHECK(store.rule("r3")->uses_by_others == 4);
  fs::remove_all(dir);
}

TEST_CASE("weight changes add up in the store and survive export and import", "[lexicon]") {
  LexiconStore store(":memory:");
  store.add_definition({0, "h", {"b"}, "ana", 1}, {make_rule(1, "ana")});
  // Two accepts (possibly from two processes): changes to the same weight are summed.
  store.record_accept({{"r1", 1, 0}}, "global",
                      std::vector<flipper::naturalization::StoredWeightChange>{
                          {"", "f:a", 0.5, 0.25}, {"", "f:b", -1, 1}});
  store.record_accept({{"r1", 0, 1}}, "global",
                      std::vector<flipper::naturalization::StoredWeightChange>{
                          {"", "f:a", 0.25, 0.0625}, {"ana", "f:a", 2, 4}});
  store.record_accept({}, "user:bob",
                      std::vector<flipper::naturalization::StoredWeightChange>{{"", "f:z", 3, 9}});
  auto check = [](const LexiconStore& s) {
    const auto w = s.weight_changes("global");
    REQUIRE(w.size() == 3);  // ordered by model, feature
    CHECK((w[0].model == "" && w[0].feature == "f:a" && w[0].weight == 0.75 && w[0].aux == 0.3125));
    CHECK((w[1].model == "" && w[1].feature == "f:b" && w[1].weight == -1 && w[1].aux == 1));
    CHECK((w[2].model == "ana" && w[2].feature == "f:a" && w[2].weight == 2 && w[2].aux == 4));
    REQUIRE(s.weight_changes("user:bob").size() == 1);
    CHECK(s.weight_changes("user:bob")[0].weight == 3);
    CHECK(s.rule("r1")->uses_by_author == 1);
    CHECK(s.rule("r1")->uses_by_others == 1);
  };
  check(store);
  CHECK_FALSE(store.load_weights("global"));  // no whole state was written
  std::stringstream text;
  store.export_jsonl(text);
  LexiconStore copy(":memory:");
  copy.import_jsonl(text);
  check(copy);
}

TEST_CASE("export and import as JSON Lines round-trip", "[lexicon]") {
  LexiconStore a(":memory:");
  a.add_definition({0, "pick 3 items", {"repeat 3 times pick item"}, "ana", 5},
                   {make_rule(1, "ana"), make_rule(2, "ana")});
  a.mark_deleted("r2", 6);
  a.record_accept({{"r1", 1, 3}}, "global", "{\"w\":{}}");
  std::stringstream text;
  a.export_jsonl(text);
  const std::string exported = text.str();
  CHECK(std::count(exported.begin(), exported.end(), '\n') == 4);

  LexiconStore b(":memory:");
  CHECK(b.import_jsonl(text) == 4);
  std::stringstream again;
  b.export_jsonl(again);
  CHECK(again.str() == exported);
  CHECK(b.rules().size() == 1);
  CHECK(b.rule("r1")->uses_by_others == 3);

  std::stringstream bad("{\"type\":\"rule\"}\n");
  CHECK_THROWS_AS(b.import_jsonl(bad), flipper::sdk::Error);
}

TEST_CASE("a corrupt or foreign file is refused by name and left untouched", "[lexicon]") {
  const fs::path dir = fresh_dir("corrupt");
  fs::create_directories(dir);
  const fs::path garbage = dir / "garbage.db";
  {
    std::ofstream out(garbage, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>(i * 37 + 11));
  }
  const std::string before = slurp(garbage);
  try {
    LexiconStore store(garbage.string());
    FAIL("opened a garbage file");
  } catch (const flipper::sdk::Error& e) {
    CHECK(e.code() == "lexicon_corrupt");
    CHECK_THAT(e.what(), Catch::Contains(garbage.string()));
  }
  CHECK(slurp(garbage) == before);
  CHECK_FALSE(fs::exists(dir / "garbage.db-wal"));

  const fs::path foreign = dir / "foreign.db";
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(foreign.string().c_str(), &db) == SQLITE_OK);
  REQUIRE(sqlite3_exec(db, "CREATE TABLE t(x); INSERT INTO t VALUES (1);", nullptr, nullptr,
                       nullptr) == SQLITE_OK);
  sqlite3_close(db);
  const std::string foreign_before = slurp(foreign);
  try {
    LexiconStore store(foreign.string());
    FAIL("opened a foreign database");
  } catch (const flipper::sdk::Error& e) {
    CHECK(e.code() == "bad_lexicon");
    CHECK_THAT(e.what(), Catch::Contains("not a Flipper lexicon"));
  }
  CHECK(slurp(foreign) == foreign_before);

  // A truncated lexicon (a torn copy) is refused as well.
  const fs::path torn = dir / "torn.db";
  {
    LexiconStore store(torn.string());
    for (int i = 1; i <= 200; ++i)
      store.add_definition({0, "h" + std::to_string(i), {"b"}, "ana", i}, {make_rule(i, "ana")});
  }
  fs::resize_file(torn, fs::file_size(torn) / 2);
  fs::remove(dir / "torn.db-wal");
  CHECK_THROWS_AS(LexiconStore(torn.string()), flipper::sdk::Error);
  fs::remove_all(dir);
}
