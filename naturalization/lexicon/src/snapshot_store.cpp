// The rule snapshot's row in the store (docs/naturalization.md §5 "Start-up at scale"): a derived
// cache next to the rules, in its own table that older builds ignore (no schema change).
#include <sqlite3.h>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/rule_snapshot.hpp"
#include "flipper/sdk/errors.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {

namespace {

constexpr const char* kCreateRuleSnapshot =
    "CREATE TABLE IF NOT EXISTS rule_snapshot("
    "id INTEGER PRIMARY KEY CHECK (id = 1), format INTEGER NOT NULL, created_mark INTEGER NOT "
    "NULL, deleted_mark INTEGER NOT NULL, rows INTEGER NOT NULL, rules INTEGER NOT NULL, checksum "
    "INTEGER NOT NULL, data BLOB NOT NULL)";

/// A cache write waits this long for other writers at most, then gives up (start-up must not
/// stall behind a busy store for the default lexicon.busy_timeout_ms).
constexpr int kSaveBusyMs = 50;

std::int64_t one_int(sqlite::Db& db, const char* sql, std::int64_t arg) {
  sqlite::Stmt s(db, sql);
  s.bind(1, arg);
  s.step();
  return s.int64(0);
}

}  // namespace

std::optional<StoredSnapshot> LexiconStore::load_snapshot(SnapshotMiss* miss) const {
  auto& db = *impl_->db;
  SnapshotMiss why = SnapshotMiss::none;
  auto fail = [&](SnapshotMiss m) -> std::optional<StoredSnapshot> {
    if (miss) {
      *miss = m;
    }
    return std::nullopt;
  };
  if (miss) {
    *miss = why;
  }
  if (impl_->path == ":memory:") {
    return fail(SnapshotMiss::absent);
  }
  sqlite::ReadTransaction read(db);
  {
    sqlite::Stmt has(db, "SELECT 1 FROM sqlite_master WHERE type='table' AND name='rule_snapshot'");
    if (!has.step()) {
      return fail(SnapshotMiss::absent);
    }
  }
  sqlite::Stmt s(db,
                 "SELECT format, created_mark, deleted_mark, rows, rules, checksum, data "
                 "FROM rule_snapshot WHERE id = 1");
  if (!s.step()) {
    return fail(SnapshotMiss::absent);
  }
  if (s.int64(0) != kRuleSnapshotFormat) {
    return fail(SnapshotMiss::other_format);
  }
  StoredSnapshot out;
  out.mark = {s.int64(1), s.int64(2)};
  const std::int64_t rows = s.int64(3);
  out.rules = s.int64(4);
  const auto checksum = static_cast<std::uint64_t>(s.int64(5));
  out.data = s.blob(6);
  if (snapshot_checksum(out.data) != checksum) {
    return fail(SnapshotMiss::damaged);
  }
  // Fits the store: every row below the mark was there when it was taken (an import of old rows,
  // or a store swapped for an older copy, invalidates it).
  sqlite::Stmt m(db,
                 "SELECT (SELECT coalesce(max(created), 0) FROM rules), "
                 "(SELECT coalesce(max(deleted_seq), 0) FROM rules), (SELECT count(*) FROM rules)");
  m.step();
  const std::int64_t after =
      one_int(db, "SELECT count(*) FROM rules WHERE created > ?", out.mark.created);
  if (out.mark.created > m.int64(0) || out.mark.deleted > m.int64(1) ||
      m.int64(2) != rows + after || out.rules < 0 || out.rules > rows) {
    return fail(SnapshotMiss::inconsistent);
  }
  out.changed =
      after + one_int(db, "SELECT count(*) FROM rules WHERE deleted_seq > ?", out.mark.deleted);
  return out;
}

bool LexiconStore::save_snapshot(const LiveRulesRead& read, std::int64_t rules,
                                 const std::string& data) {
  auto& db = *impl_->db;
  if (impl_->path == ":memory:" || db.read_only()) {
    return false;
  }
  const int timeout = db.busy_timeout_ms();
  db.set_busy_timeout_ms(kSaveBusyMs);
  try {
    sqlite::Transaction tx(db);
    db.exec(kCreateRuleSnapshot);
    // Start-up reads the used rules' counters through this (a lexicon big enough for a snapshot
    // mostly holds unused rules; the full table scan was a tenth of a warm start).
    db.exec(
        "CREATE INDEX IF NOT EXISTS rule_uses_used ON rule_uses(rule) "
        "WHERE by_author <> 0 OR by_others <> 0");
    sqlite::Stmt up(
        db,
        "INSERT INTO rule_snapshot(id, format, created_mark, deleted_mark, rows, rules, "
        "checksum, data) VALUES (1,?,?,?,?,?,?,?) ON CONFLICT(id) DO UPDATE SET "
        "format = excluded.format, created_mark = excluded.created_mark, "
        "deleted_mark = excluded.deleted_mark, rows = excluded.rows, "
        "rules = excluded.rules, checksum = excluded.checksum, data = excluded.data "
        "WHERE excluded.created_mark >= created_mark "
        "AND excluded.deleted_mark >= deleted_mark");
    up.bind(1, std::int64_t{kRuleSnapshotFormat})
        .bind(2, read.mark.created)
        .bind(3, read.mark.deleted)
        .bind(4, read.rows)
        .bind(5, rules)
        .bind(6, static_cast<std::int64_t>(snapshot_checksum(data)))
        .bind_blob(7, data)
        .run();
    tx.commit();
  } catch (const sdk::Error& e) {
    db.set_busy_timeout_ms(timeout);
    if (lexicon_codes::is_store_fault(e.code()) && e.code() != lexicon_codes::kCorrupt) {
      return false;
    }
    throw;
  }
  db.set_busy_timeout_ms(timeout);
  return true;
}

}  // namespace flipper::naturalization
