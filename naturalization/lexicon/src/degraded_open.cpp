#include "degraded_open.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include "flipper/naturalization/lexicon_store.hpp"

namespace flipper::naturalization {

namespace fs = std::filesystem;

namespace {

bool refused_write(const std::string& path) {
  return ::access(path.c_str(), W_OK) != 0 && (errno == EACCES || errno == EROFS || errno == EPERM);
}

}  // namespace

const char* degraded_reason(const std::string& path, const sdk::Error& error) {
  const std::string& code = error.code();
  if (code == lexicon_codes::kReadOnly) return lexicon_codes::kReadOnly;
  if (code == lexicon_codes::kFull) return lexicon_codes::kFull;
  if (code != lexicon_codes::kBadLexicon) return nullptr;  // corrupt, busy: not a degradation
  // SQLite reports some of these as "unable to open" (the WAL's files cannot be created).
  struct statvfs fsinfo {};
  if (::statvfs(path.c_str(), &fsinfo) == 0 && (fsinfo.f_flag & ST_RDONLY) != 0)
    return lexicon_codes::kReadOnly;
  const fs::path parent = fs::path(path).parent_path();
  const fs::path dir = parent.empty() ? fs::path(".") : parent;
  if (refused_write(path) || refused_write(dir.string())) return lexicon_codes::kReadOnly;
  if (::statvfs(path.c_str(), &fsinfo) == 0 && fsinfo.f_bavail == 0) return lexicon_codes::kFull;
  return nullptr;
}

std::unique_ptr<sqlite::Db> open_for_reading(const std::string& path, int busy_timeout_ms,
                                             const sdk::Error& cause) {
  std::error_code ec;
  const auto wal_bytes = fs::file_size(path + "-wal", ec);
  if (ec || wal_bytes == 0)
    return std::make_unique<sqlite::Db>(path, sqlite::Db::ReadOnly{"immutable=1"}, busy_timeout_ms);
  try {
    auto db = std::make_unique<sqlite::Db>(path, sqlite::Db::ReadOnly{"mode=ro"}, busy_timeout_ms);
    db->exec("SELECT count(*) FROM sqlite_master");  // reads through the WAL index now
    return db;
  } catch (const sdk::Error&) {
    throw sdk::Error(cause.code(),
                     std::string(cause.what()) +
                         "; its write-ahead log holds commits that cannot be read without "
                         "write access to the store's folder, so it is not served read-only");
  }
}

}  // namespace flipper::naturalization
