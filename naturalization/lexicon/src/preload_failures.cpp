// The preload report's rows in the store (docs/naturalization.md §5): which definitions of a
// `lexicon.preload` file did not load at the last start, in a table of their own that older
// builds ignore (no schema change; created with the first failure).
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/sdk/errors.hpp"
#include "sqlite_handle.hpp"
#include "store_impl.hpp"

namespace flipper::naturalization {

namespace {

constexpr const char* kCreatePreloadFailures =
    "CREATE TABLE IF NOT EXISTS preload_failures("
    "file TEXT NOT NULL, line INTEGER NOT NULL, head TEXT NOT NULL, author TEXT NOT NULL, "
    "code TEXT NOT NULL, message TEXT NOT NULL, time INTEGER NOT NULL, PRIMARY KEY(file, line))";

bool has_table(sqlite::Db& db) {
  sqlite::Stmt s(db, "SELECT 1 FROM sqlite_master WHERE type='table' AND name='preload_failures'");
  return s.step();
}

}  // namespace

void insert_preload_failures(sqlite::Db& db, const std::vector<PreloadFailure>& failures) {
  if (failures.empty()) return;
  db.exec(kCreatePreloadFailures);
  sqlite::Stmt ins(db,
                   "INSERT OR REPLACE INTO preload_failures(file, line, head, author, code, "
                   "message, time) VALUES (?,?,?,?,?,?,?)");
  for (const auto& f : failures) {
    ins.bind(1, f.file).bind(2, f.line).bind(3, f.head).bind(4, f.author).bind(5, f.code);
    ins.bind(6, f.message).bind(7, f.time).run();
  }
}

bool LexiconStore::record_preload_failures(const std::string& file,
                                           const std::vector<PreloadFailure>& failures) {
  auto& db = *impl_->db;
  if (failures.empty()) {  // only clear what an earlier start recorded for this file
    if (!has_table(db)) return true;
    sqlite::Stmt any(db, "SELECT 1 FROM preload_failures WHERE file = ?");
    if (!any.bind(1, file).step()) return true;
  }
  if (db.read_only() || db.write_refusal()) return false;
  try {
    sqlite::Transaction tx(db);
    if (has_table(db)) {
      sqlite::Stmt clear(db, "DELETE FROM preload_failures WHERE file = ?");
      clear.bind(1, file).run();
    }
    insert_preload_failures(db, failures);
    tx.commit();
  } catch (const sdk::Error& e) {
    if (lexicon_codes::is_store_fault(e.code()) && e.code() != lexicon_codes::kCorrupt)
      return false;
    throw;
  }
  return true;
}

std::vector<PreloadFailure> LexiconStore::preload_failures() const {
  auto& db = *impl_->db;
  std::vector<PreloadFailure> out;
  if (!has_table(db)) return out;
  sqlite::Stmt s(db,
                 "SELECT file, line, head, author, code, message, time FROM preload_failures "
                 "ORDER BY file, line");
  while (s.step())
    out.push_back({s.text(0), s.int64(1), s.text(2), s.text(3), s.text(4), s.text(5), s.int64(6)});
  return out;
}

}  // namespace flipper::naturalization
