#pragma once
// LexiconStore's state, shared by the files that implement it (lexicon_store.cpp,
// snapshot_store.cpp).
#include <memory>
#include <optional>
#include <string>

#include "flipper/naturalization/lexicon_store.hpp"
#include "sqlite_handle.hpp"

namespace flipper::kernel {

struct LexiconStore::Impl {
  std::unique_ptr<sqlite::Db> db;
  std::string path;
  std::unique_ptr<sqlite::Stmt> data_version;  // cached: checked before every parse
  std::optional<std::int64_t> last_data_version;
};

}  // namespace flipper::kernel
