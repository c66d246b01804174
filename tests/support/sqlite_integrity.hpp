#pragma once
// SQLite's own integrity check of a store file, for the tests that kill writers (link SQLite3).
#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <string>

namespace flipper::testsupport {

/// The first row of `PRAGMA integrity_check` ("ok" for a sound file).
inline std::string sqlite_integrity(const std::string& path) {
  sqlite3* db = nullptr;
  const int opened = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr);
  if (opened != SQLITE_OK) sqlite3_close(db);  // a handle is allocated even when opening fails
  REQUIRE(opened == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK);
  REQUIRE(sqlite3_step(st) == SQLITE_ROW);
  std::string result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return result;
}

}  // namespace flipper::testsupport
