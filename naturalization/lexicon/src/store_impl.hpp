#pragma once
// LexiconStore's state, shared by the files that implement it (lexicon_store.cpp,
// snapshot_store.cpp).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_handle.hpp"
#include "wal_index_watch.hpp"

namespace flipper::naturalization {

/// Adds preload failures to the store inside the caller's write transaction (creating their
/// table when there are any).
void insert_preload_failures(sqlite::Db& db, const std::vector<PreloadFailure>& failures);

struct LexiconStore::Impl {
  std::unique_ptr<sqlite::Db> db;
  std::string path;
  std::string site;  // lexicon.site, in every history entry this process writes
  std::unique_ptr<sqlite::Stmt> data_version;  // cached: checked before every parse
  std::optional<std::int64_t> last_data_version;
  // The WAL index's header when data_version was last read: while it is unchanged, nothing was
  // committed and changed_elsewhere() answers without SQLite (wal_index_watch.hpp). The watch
  // reads the connection's own mapping of the index: it goes with `db`.
  WalIndexWatch wal_index;
  bool wal_index_tried = false;
  std::optional<WalIndexWatch::Header> header_at_last_read;
  std::uint64_t data_version_reads = 0;
};

}  // namespace flipper::naturalization
