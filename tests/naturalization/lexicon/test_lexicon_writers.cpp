// Many writers on one store (docs/naturalization.md §5): ids assigned by SQLite inside the defining
// transaction, busy handling with a bounded wait, authorship checked in the delete's transaction,
// incremental change pick-up, and a distinct code per store fault (busy, full, read-only, corrupt).
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"

namespace fs = std::filesystem;
using flipper::naturalization::DeleteStatus;
using flipper::naturalization::LexiconStore;
using flipper::naturalization::LexiconStoreOptions;
using flipper::naturalization::StoredRule;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("flipper-writers-" + name + "-" + std::to_string(std::random_device{}()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

StoredRule rule_of(const std::string& author, const std::string& word) {
  StoredRule r;
  r.created = 1;  // what a process-local counter would say; the store must not use it
  r.id = "r1";
  r.lhs = "$Action";
  r.rhs = {word, "$Number"};
  r.semantics = "{repeat $1 times {pick item }}";
  r.author = author;
  r.head = word + " 3";
  r.body = {"repeat 3 times pick item"};
  r.how = "simple";
  return r;
}

/// The code of the sdk::Error `f` throws ("" when it does not throw); `message` gets its text.
template <class F>
std::string code_of(F&& f, std::string* message = nullptr) {
  try {
    f();
  } catch (const flipper::sdk::Error& e) {
    if (message) *message = e.what();
    return e.code();
  }
  return "";
}

/// Another process's write lock, held until destroyed.
struct LockHolder {
  sqlite3* db = nullptr;
  explicit LockHolder(const std::string& path) {
    REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
    REQUIRE(sqlite3_exec(db, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr) == SQLITE_OK);
  }
  ~LockHolder() {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
};

}  // namespace

TEST_CASE("two connections defining at once get distinct ids and keep both rules",
          "[lexicon][writers]") {
  const fs::path dir = fresh_dir("ids");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore ana_process(path), bob_process(path);
  const auto a =
      ana_process.commit_definition({0, "glorp 3", {"b"}, "ana", 1}, {rule_of("ana", "glorp")});
  const auto b =
      bob_process.commit_definition({0, "blick 3", {"b"}, "bob", 1}, {rule_of("bob", "blick")});
  REQUIRE(a.rules.size() == 1);
  REQUIRE(b.rules.size() == 1);
  CHECK(a.rules[0].id == "r1");
  CHECK(b.rules[0].id == "r2");  // assigned in bob's transaction, after ana's commit
  CHECK(b.rules[0].created == 2);
  CHECK(a.definition != b.definition);
  LexiconStore check(path);
  const auto rules = check.rules();
  REQUIRE(rules.size() == 2);
  CHECK(rules[0].author == "ana");
  CHECK(rules[1].author == "bob");
  // bob may not delete ana's rule, and the check happens with the delete, in the store.
  CHECK(bob_process.delete_rule("r1", "bob", 5, [](const std::string&) { return true; }).status ==
        DeleteStatus::forbidden);
  CHECK(bob_process.delete_rule("r1", "bob", 5, [](const std::string&) { return false; }).status ==
        DeleteStatus::not_found);  // hidden from bob: nothing about its owner
  CHECK(bob_process.delete_rule("r9", "bob", 5, {}).status == DeleteStatus::not_found);
  CHECK(check.rule("r1")->deleted == false);
  CHECK(ana_process.delete_rule("r1", "ana", 5, {}).status == DeleteStatus::deleted);
  CHECK(bob_process.delete_rule("r1", "ana", 6, {}).status == DeleteStatus::not_found);  // gone
  fs::remove_all(dir);
}

TEST_CASE("changes_since reads other connections' rules and deletions incrementally",
          "[lexicon][writers]") {
  const fs::path dir = fresh_dir("changes");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore reader(path), writer(path);
  CHECK(reader.changed_elsewhere());  // first look
  auto c0 = reader.changes_since({});
  CHECK(c0.added.empty());
  CHECK_FALSE(reader.changed_elsewhere());
  writer.commit_definition({0, "glorp 3", {"b"}, "ana", 1},
                           {rule_of("ana", "glorp"), rule_of("ana", "glorq")});
  CHECK(reader.changed_elsewhere());
  const auto c1 = reader.changes_since(c0.mark);
  REQUIRE(c1.added.size() == 2);
  CHECK(c1.added[0].id == "r1");
  CHECK(c1.added[1].id == "r2");
  CHECK(c1.mark.created == 2);
  writer.delete_rule("r1", "ana", 3, {});
  writer.commit_definition({0, "blick 3", {"b"}, "bob", 1}, {rule_of("bob", "blick")});
  CHECK(reader.changed_elsewhere());
  const auto c2 = reader.changes_since(c1.mark);
  REQUIRE(c2.added.size() == 1);  // only what is new
  CHECK(c2.added[0].id == "r3");
  CHECK(c2.deleted == std::vector<std::string>{"r1"});
  const auto c3 = reader.changes_since(c2.mark);
  CHECK(c3.added.empty());
  CHECK(c3.deleted.empty());
  CHECK_FALSE(reader.changed_elsewhere());
  fs::remove_all(dir);
}

TEST_CASE("changed_elsewhere asks SQLite only when the WAL index's header moved",
          "[lexicon][writers]") {
  const fs::path dir = fresh_dir("watch");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore reader(path), writer(path);
  CHECK(reader.changed_elsewhere());  // first look: asks, then maps the index
  CHECK(reader.data_version_reads() == 1);
  CHECK_FALSE(reader.changed_elsewhere());  // asks once more, now with the header read before
  CHECK(reader.data_version_reads() == 2);
  for (int i = 0; i < 100; ++i) CHECK_FALSE(reader.changed_elsewhere());
  CHECK(reader.data_version_reads() == 2);  // nothing committed: the header alone answers

  writer.commit_definition({0, "glorp 3", {"b"}, "ana", 1}, {rule_of("ana", "glorp")});
  CHECK(reader.changed_elsewhere());
  CHECK(reader.data_version_reads() == 3);
  CHECK_FALSE(reader.changed_elsewhere());
  CHECK(reader.data_version_reads() == 3);

  // Its own commit moves the header too: SQLite is asked, and says "not elsewhere".
  reader.commit_definition({0, "blick 3", {"b"}, "bob", 1}, {rule_of("bob", "blick")});
  CHECK_FALSE(reader.changed_elsewhere());
  CHECK(reader.data_version_reads() == 4);

  // Another process's commit.
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    int status = 0;
    try {
      LexiconStore other(path);
      other.commit_definition({0, "zorp 3", {"b"}, "eve", 1}, {rule_of("eve", "zorp")});
    } catch (...) {
      status = 1;
    }
    _exit(status);
  }
  int status = -1;
  REQUIRE(waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  CHECK(reader.changed_elsewhere());
  CHECK(reader.data_version_reads() == 5);
  CHECK(reader.changes_since({}).added.size() == 3);

  // An in-memory store has no shared index: every call asks.
  LexiconStore memory(":memory:");
  for (int i = 0; i < 3; ++i) memory.changed_elsewhere();
  CHECK(memory.data_version_reads() == 3);
  fs::remove_all(dir);
}

TEST_CASE("accept counters add up across connections", "[lexicon][writers]") {
  const fs::path dir = fresh_dir("uses");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore a(path), b(path);
  a.commit_definition({0, "glorp 3", {"b"}, "ana", 1}, {rule_of("ana", "glorp")});
  a.record_accept({{"r1", 1, 0}}, "global", "wa");
  const auto totals = b.record_accept({{"r1", 0, 1}}, "global", "wb");
  REQUIRE(totals.size() == 1);
  CHECK(totals[0].by_author == 1);  // not overwritten by b's view
  CHECK(totals[0].by_others == 1);
  CHECK(a.rule("r1")->uses_by_author == 1);
  CHECK(a.rule("r1")->uses_by_others == 1);
  fs::remove_all(dir);
}

TEST_CASE("a writer waits for another's lock, then answers lexicon_busy naming the file",
          "[lexicon][writers][faults]") {
  const fs::path dir = fresh_dir("busy");
  const std::string path = (dir / "lexicon.db").string();
  LexiconStore store(path, LexiconStoreOptions{200, 0});
  {
    LockHolder other(path);
    std::string message;
    const auto t0 = std::chrono::steady_clock::now();
    CHECK(code_of(
              [&] {
                store.add_definition({0, "h", {"b"}, "ana", 1}, {rule_of("ana", "x")});
              },
              &message) == "lexicon_busy");
    const auto waited = std::chrono::steady_clock::now() - t0;
    CHECK(waited >= std::chrono::milliseconds(200));  // it did wait (bounded retries) ...
    CHECK(waited < std::chrono::seconds(5));          // ... and not forever
    CHECK_THAT(message, Catch::Contains(path));
    CHECK_THAT(message, Catch::Contains("busy"));
    CHECK_THAT(message, Catch::Contains("lexicon.busy_timeout_ms = 200"));
  }
  CHECK(store.definitions().empty());                                      // nothing half-written
  store.add_definition({0, "h", {"b"}, "ana", 1}, {rule_of("ana", "x")});  // lock gone: works
  CHECK(store.rules().size() == 1);
  fs::remove_all(dir);
}

TEST_CASE("a full store answers lexicon_full and keeps what it had", "[lexicon][writers][faults]") {
  // Simulated with SQLite's max_page_count (a page cap on the file), the same SQLITE_FULL a full
  // device gives; no mount or loop device is needed.
  const fs::path dir = fresh_dir("full");
  const std::string path = (dir / "lexicon.db").string();
  { LexiconStore create(path); }
  LexiconStore store(path, LexiconStoreOptions{1000, 12});
  std::string message;
  std::string code;
  int stored = 0;
  for (int i = 0; i < 2000 && code.empty(); ++i) {
    StoredRule r = rule_of("ana", "w" + std::to_string(i));
    r.body = {std::string(400, 'x')};
    code = code_of(
        [&] {
          store.add_definition({0, "h", {std::string(400, 'y')}, "ana", i}, {r});
        },
        &message);
    if (code.empty()) ++stored;
  }
  CHECK(code == "lexicon_full");
  CHECK_THAT(message, Catch::Contains(path));
  CHECK_THAT(message, Catch::Contains("full"));
  CHECK(stored > 0);
  LexiconStore reopened(path);
  CHECK(static_cast<int>(reopened.definitions().size()) == stored);  // all acknowledged kept
  CHECK(static_cast<int>(reopened.rules().size()) == stored);
  fs::remove_all(dir);
}

TEST_CASE("a read-only store answers lexicon_read_only naming the file",
          "[lexicon][writers][faults]") {
  const fs::path dir = fresh_dir("ro");
  const std::string path = (dir / "lexicon.db").string();
  {
    LexiconStore create(path);
    create.add_definition({0, "h", {"b"}, "ana", 1}, {rule_of("ana", "x")});
  }
  fs::permissions(path, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                           fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  // Root ignores permissions: the check runs in a child that drops to 'nobody' first.
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) _exit(10);
    std::string message;
    std::string code = code_of(
        [&] {
          LexiconStore store(path);
          if (store.rules().size() != 1) _exit(11);  // reading works
          store.add_definition({0, "h2", {"b"}, "ana", 2}, {rule_of("ana", "y")});
        },
        &message);
    if (code != "lexicon_read_only") {
      std::fprintf(stderr, "code '%s': %s\n", code.c_str(), message.c_str());
      _exit(12);
    }
    if (message.find(path) == std::string::npos || message.find("read-only") == std::string::npos)
      _exit(13);
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  fs::permissions(dir, fs::perms::owner_all);
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  fs::remove_all(dir);
}

TEST_CASE("a garbage file is lexicon_corrupt, a foreign database bad_lexicon",
          "[lexicon][writers][faults]") {
  const fs::path dir = fresh_dir("corrupt");
  const fs::path garbage = dir / "garbage.db";
  {
    std::ofstream out(garbage, std::ios::binary);
    for (int i = 0; i < 4096; ++i) out.put(static_cast<char>(i * 37 + 11));
  }
  std::string message;
  CHECK(code_of([&] { LexiconStore s(garbage.string()); }, &message) == "lexicon_corrupt");
  CHECK_THAT(message, Catch::Contains(garbage.string()));
  CHECK_THAT(message, Catch::Contains("corrupt"));
  const fs::path foreign = dir / "foreign.db";
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(foreign.string().c_str(), &db) == SQLITE_OK);
  REQUIRE(sqlite3_exec(db, "CREATE TABLE t(x)", nullptr, nullptr, nullptr) == SQLITE_OK);
  sqlite3_close(db);
  CHECK(code_of([&] { LexiconStore s(foreign.string()); }) == "bad_lexicon");
  fs::remove_all(dir);
}

TEST_CASE("a version 1 store is upgraded in place and keeps its deletions", "[lexicon][writers]") {
  const fs::path dir = fresh_dir("v1");
  const std::string path = (dir / "lexicon.db").string();
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
  REQUIRE(sqlite3_exec(db, R"sql(
CREATE TABLE flipper_schema(version INTEGER NOT NULL);
INSERT INTO flipper_schema VALUES (1);
CREATE TABLE definitions(id INTEGER PRIMARY KEY, head TEXT NOT NULL, body TEXT NOT NULL,
  author TEXT NOT NULL, time INTEGER NOT NULL);
CREATE TABLE rules(id TEXT PRIMARY KEY, created INTEGER NOT NULL UNIQUE, definition INTEGER NOT NULL,
  lhs TEXT NOT NULL, rhs TEXT NOT NULL, template TEXT NOT NULL, author TEXT NOT NULL,
  head TEXT NOT NULL, body TEXT NOT NULL, how TEXT NOT NULL,
  deleted INTEGER NOT NULL DEFAULT 0, deleted_at INTEGER);
CREATE TABLE rule_uses(rule TEXT PRIMARY KEY, by_author INTEGER NOT NULL, by_others INTEGER NOT NULL);
CREATE TABLE scorer_state(key TEXT PRIMARY KEY, state TEXT NOT NULL);
INSERT INTO definitions VALUES (1, 'h', '["b"]', 'ana', 1);
INSERT INTO rules VALUES ('r1', 1, 1, '$Action', '["glorp","$Number"]', '{repeat $1 times {pick item }}',
  'ana', 'h', '["b"]', 'simple', 1, 5);
INSERT INTO rules VALUES ('r2', 2, 1, '$Action', '["glorq","$Number"]', '{repeat $1 times {pick item }}',
  'ana', 'h', '["b"]', 'simple', 0, NULL);
)sql",
                       nullptr, nullptr, nullptr) == SQLITE_OK);
  sqlite3_close(db);
  LexiconStore store(path);
  CHECK(store.rules().size() == 1);
  CHECK(store.rules(true).size() == 2);
  const auto changes = store.changes_since({});
  CHECK(changes.deleted == std::vector<std::string>{"r1"});
  CHECK(changes.mark.created == 2);
  const auto next = store.commit_definition({0, "h3", {"b"}, "bob", 2}, {rule_of("bob", "zz")});
  CHECK(next.rules[0].id == "r3");
  fs::remove_all(dir);
}
