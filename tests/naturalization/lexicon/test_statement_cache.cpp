// The connection's statement cache (src/sqlite_handle.hpp, docs/naturalization.md §5 "Durability
// and latency"): a statement is compiled once per text and connection, comes back reset (no read
// snapshot held, no binding left), Stmts of one text nest, the cache keeps at most
// kIdleStatements statements, and a failed statement run through it reports what exec reports.
// And the background checkpoints' requests: past kCheckpointPages, then once per kRequestEvery
// frames (docs/naturalization.md §5).
#include <sqlite3.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "sqlite_handle.hpp"

namespace fs = std::filesystem;
using flipper::naturalization::sqlite::Db;
using flipper::naturalization::sqlite::Stmt;

namespace {

/// A fresh store file in WAL mode with one table t(x) of three rows.
struct CacheStore {
  fs::path dir;
  std::string path;
  CacheStore() {
    dir = fs::temp_directory_path() / ("flipper-stmt-cache-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    path = (dir / "store.db").string();
    Db db(path, true, 1000);
    db.exec(
        "PRAGMA journal_mode=WAL; CREATE TABLE t(x INTEGER); "
        "INSERT INTO t VALUES (1), (2), (3)");
  }
  ~CacheStore() { fs::remove_all(dir); }
};

/// The statements the connection holds (in use or idle).
int statements_on(const Db& db) {
  int n = 0;
  for (sqlite3_stmt* s = sqlite3_next_stmt(db.raw(), nullptr); s != nullptr;
       s = sqlite3_next_stmt(db.raw(), s))
    ++n;
  return n;
}

}  // namespace

TEST_CASE("statement cache: one compiled statement per text, reused", "[lexicon][stmt-cache]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  for (int round = 0; round < 5; ++round) {
    Stmt s(db, "SELECT sum(x) FROM t WHERE x >= ?");
    s.bind(1, std::int64_t{2});
    REQUIRE(s.step());
    CHECK(s.int64(0) == 5);
  }
  CHECK(statements_on(db) == 1);
  // BEGIN and COMMIT through Db::run are cached too.
  for (int round = 0; round < 3; ++round) {
    db.run("BEGIN");
    db.run("COMMIT");
  }
  CHECK(statements_on(db) == 3);
}

TEST_CASE("statement cache: a statement comes back reset, without its bindings",
          "[lexicon][stmt-cache]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  {
    Stmt s(db, "SELECT x, ? FROM t ORDER BY x");
    s.bind(1, std::string_view("stale"));
    REQUIRE(s.step());  // a row pending: a read snapshot is open
    CHECK(s.int64(0) == 1);
  }
  // No snapshot survives the Stmt: another connection's write and a TRUNCATE checkpoint, which
  // waits for every reader, go through at once.
  Db other(store.path, false, 1000);
  other.exec("INSERT INTO t VALUES (4)");
  int log = -1, done = -1;
  REQUIRE(sqlite3_wal_checkpoint_v2(other.raw(), "main", SQLITE_CHECKPOINT_TRUNCATE, &log, &done) ==
          SQLITE_OK);
  CHECK(log == 0);
  // The same text again: the cached statement, from its first row, its parameter unbound (NULL),
  // and it sees the other connection's row.
  Stmt s(db, "SELECT x, ? FROM t ORDER BY x");
  CHECK(statements_on(db) == 1);
  int rows = 0;
  while (s.step()) {
    ++rows;
    CHECK(s.int64(0) == rows);
    CHECK(s.is_null(1));
  }
  CHECK(rows == 4);
}

TEST_CASE("statement cache: Stmts of one text nest", "[lexicon][stmt-cache]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  const char* sql = "SELECT x FROM t ORDER BY x";
  std::string pairs;
  {
    Stmt outer(db, sql);
    while (outer.step()) {
      Stmt inner(db, sql);
      while (inner.step()) pairs += std::to_string(outer.int64(0)) + std::to_string(inner.int64(0));
    }
  }
  CHECK(pairs == "111213212223313233");
  // Both went back to the cache: two idle statements of one text.
  CHECK(statements_on(db) == 2);
  Stmt a(db, sql), b(db, sql);
  CHECK(statements_on(db) == 2);
}

TEST_CASE("statement cache: at most kIdleStatements idle statements, for N and N + 1 texts",
          "[lexicon][stmt-cache]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  const auto n = static_cast<int>(Db::kIdleStatements);
  auto run_texts = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      Stmt s(db, ("SELECT " + std::to_string(i)).c_str());
      REQUIRE(s.step());
      CHECK(s.int64(0) == i);
    }
  };
  run_texts(0, n);
  CHECK(statements_on(db) == n);
  run_texts(n, n + 1);  // the cache is full: finalized when given back
  CHECK(statements_on(db) == n);
  // Texts past kStatementTexts are never kept either, and the cache stays bounded.
  CHECK(db.statement_texts() == static_cast<std::size_t>(n) + 1);
  const auto texts = static_cast<int>(Db::kStatementTexts);
  run_texts(n + 1, texts);
  CHECK(db.statement_texts() == Db::kStatementTexts);
  run_texts(texts, texts + 100);
  CHECK(db.statement_texts() == Db::kStatementTexts);
  CHECK(statements_on(db) == n);
  // A cached text is still served from the cache.
  run_texts(0, 1);
  CHECK(statements_on(db) == n);
}

TEST_CASE("statement cache: a failed run reports as exec does, and its statement is reusable",
          "[lexicon][stmt-cache]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  db.run("BEGIN");
  std::string message, exec_message;
  try {
    db.run("BEGIN");
  } catch (const flipper::sdk::Error& e) {
    message = e.what();
    CHECK(std::string(e.code()) == "bad_lexicon");
  }
  try {
    db.exec("BEGIN");
  } catch (const flipper::sdk::Error& e) {
    exec_message = e.what();
  }
  CHECK(message == "lexicon store '" + store.path +
                       "' failed (BEGIN: cannot start a transaction within a transaction, "
                       "sqlite code 1)");
  CHECK(message == exec_message);
  db.run("COMMIT");
  db.run("BEGIN");  // the BEGIN statement that failed was given back and runs again
  db.run("COMMIT");
  CHECK(statements_on(db) == 2);
  // A statement that cannot be compiled: the same error as before the cache, nothing kept.
  try {
    Stmt s(db, "SELECT nope FROM t");
    FAIL("compiled");
  } catch (const flipper::sdk::Error& e) {
    CHECK(std::string(e.what()).find("cannot prepare statement: no such column: nope") !=
          std::string::npos);
  }
  CHECK(statements_on(db) == 2);
}

TEST_CASE(
    "background checkpoints: requested past kCheckpointPages, then once per kRequestEvery "
    "frames",
    "[lexicon][checkpoint]") {
  CacheStore store;
  Db db(store.path, false, 1000);
  db.exec("PRAGMA wal_autocheckpoint=0");
  db.checkpoint_in_background();
  // A reader holds its snapshot throughout: the log can neither restart nor be checkpointed past
  // it, so it only grows, one frame or more a commit.
  Db reader(store.path, false, 1000);
  reader.run("BEGIN");
  Stmt hold(reader, "SELECT count(*) FROM t");
  REQUIRE(hold.step());
  // The oracle: the WAL's frames after each commit, from its size (a 32-byte header, then
  // frames of a 24-byte header and one page), and the rule applied to them.
  const auto wal = store.path + "-wal";
  const std::uintmax_t page = 4096;
  std::uint64_t expected = 0;
  int last = 0, frames = 0;
  // Each commit changes one row of a one-page table: one frame, so every boundary is met
  // exactly (a request at 1,000 frames, then at 1,250, not 1,251).
  while (frames < Db::kCheckpointPages + 3 * Db::kRequestEvery + 10) {
    db.run("BEGIN IMMEDIATE");
    Stmt up(db, "UPDATE t SET x = x + 1 WHERE x = (SELECT max(x) FROM t)");
    up.run();
    db.run("COMMIT");
    const int before = frames;
    frames = static_cast<int>((fs::file_size(wal) - 32) / (page + 24));
    REQUIRE(frames == before + 1);
    if (frames >= Db::kCheckpointPages && (frames < last || frames >= last + Db::kRequestEvery)) {
      ++expected;
      last = frames;
    }
    REQUIRE(db.checkpoint_requests() == expected);
  }
  // 1,000 frames, then 1,250, 1,500 and 1,750.
  CHECK(expected == 4);
}
