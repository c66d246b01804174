#pragma once
// Raw SQL on a store file, for tests that build a store state the API never writes (a damaged
// snapshot, a rule row that does not decode). Link SQLite3.
#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

namespace flipper::naturalizetest {

/// Runs `statement` on the store at `store`.
inline void sql(const std::string& store, const std::string& statement) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(store.c_str(), &db) == SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(db, statement.c_str(), nullptr, nullptr, &err);
  const std::string message = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  INFO(statement << ": " << message);
  REQUIRE(rc == SQLITE_OK);
}

/// The integer `query` selects from the store at `store`.
inline std::int64_t sql_int(const std::string& store, const std::string& query) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(store.c_str(), &db) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, query.c_str(), -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  const std::int64_t v = sqlite3_column_int64(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  return v;
}

}  // namespace flipper::naturalizetest
