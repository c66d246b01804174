#pragma once
// LexiconStore's state, shared by the files that implement it (lexicon_store.cpp,
// snapshot_store.cpp).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_handle.hpp"

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
};

}  // namespace flipper::naturalization
