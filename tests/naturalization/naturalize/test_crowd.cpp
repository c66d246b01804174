// The crowd (docs/naturalization.md §5): 100 `flipper session` processes on one lexicon file, each
// defining, querying, accepting and deleting at once (tests/support/crowd.hpp). Runs alone
// (RUN_SERIAL): its load would disturb the kill tests' liveness floors running beside it.
#include <sqlite3.h>

#include <catch2/catch.hpp>
#include <string>

#include "crowd.hpp"
#include "session_fixture.hpp"

namespace {
const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
}  // namespace

TEST_CASE("a crowd of 100 flipper session processes on one store loses nothing",
          "[naturalize][process][writers][crowd]") {
  // Each of 100 users defines, queries, accepts, queries another user's rule, deletes one of
  // their own and tries to delete someone else's (tests/support/crowd.hpp). Three rounds per user
  // keep this under a minute on 2 cores; bash scripts/bench crowd runs 10 rounds.
  flipper::testsupport::CrowdOptions o;
  o.flipper = kFlipper;
  o.store = flipper::testsupport::scratch_path("crowd") + ".sqlite";
  o.users = 100;
  o.defines = 3;
  const auto r = flipper::testsupport::run_crowd(o);
  for (const auto& e : r.error_samples) UNSCOPED_INFO(e);
  CHECK(r.errors == 0);
  CHECK(r.acknowledged_defines == 300);
  CHECK(r.acknowledged_rules == 300);  // "<word> left" := "move left" induces one rule
  CHECK(r.lost == 0);
  CHECK(r.wrong_deletions == 0);
  CHECK(r.foreign_deletes == 0);
  CHECK(r.cross_checks >= 290);  // measured 300: only the very first definers may find none
  CHECK(r.cross_failures == 0);
  CHECK(r.integrity == "ok");
}

TEST_CASE("the crowd with rule snapshots at every start loses nothing either",
          "[naturalize][process][writers][crowd][snapshot]") {
  // Same guarantees when every process that starts after the first definitions reads and writes
  // the rule snapshot (docs/naturalization.md §5 "Start-up at scale") while others define and
  // delete: a snapshot plus the rows after its mark is exactly the store.
  flipper::testsupport::CrowdOptions o;
  o.flipper = kFlipper;
  o.store = flipper::testsupport::scratch_path("crowd-snapshot") + ".sqlite";
  o.users = 100;
  o.defines = 3;
  o.extra_sets = {"lexicon.snapshot_min_rules=1"};
  // 90 of the 100 processes start after the first acknowledged definition, so they open a store
  // with rules and read or write its snapshot, however fast the first ten are (in CI all 100 once
  // started before any definition, and no snapshot was written).
  o.early_users = 10;
  const auto r = flipper::testsupport::run_crowd(o);
  for (const auto& e : r.error_samples) UNSCOPED_INFO(e);
  CHECK(r.errors == 0);
  CHECK(r.acknowledged_defines == 300);
  CHECK(r.acknowledged_rules == 300);
  CHECK(r.lost == 0);
  CHECK(r.wrong_deletions == 0);
  CHECK(r.foreign_deletes == 0);
  CHECK(r.cross_checks >= 290);
  CHECK(r.cross_failures == 0);
  CHECK(r.integrity == "ok");
  // Some process did leave a snapshot.
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(o.store.c_str(), &db) == SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  REQUIRE(sqlite3_prepare_v2(db, "SELECT rules FROM rule_snapshot", -1, &st, nullptr) == SQLITE_OK);
  CHECK(sqlite3_step(st) == SQLITE_ROW);
  CHECK(sqlite3_column_int64(st, 0) > 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
}
