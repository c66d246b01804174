#include "wal_index_watch.hpp"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace flipper::naturalization {

namespace {

// https://sqlite.org/walformat.html: the index is made of 32 KiB regions; the first begins with
// two copies of the 48-byte header; iVersion (its first 4 bytes, native byte order) is 3007000
// and isInit (byte 12) is 1 once the index is built.
constexpr int kRegion = 32768;
constexpr std::size_t kCopy = 48;
constexpr std::uint32_t kIndexVersion = 3007000;
constexpr std::size_t kIsInit = 12;

}  // namespace

bool WalIndexWatch::map(sqlite3* db) {
  if (base_ != nullptr) return true;
  sqlite3_file* file = nullptr;
  if (sqlite3_file_control(db, "main", SQLITE_FCNTL_FILE_POINTER, &file) != SQLITE_OK ||
      file == nullptr || file->pMethods == nullptr || file->pMethods->iVersion < 2 ||
      file->pMethods->xShmMap == nullptr)
    return false;
  void volatile* region = nullptr;
  // bExtend = 0: the region SQLite already mapped, never a new one.
  if (file->pMethods->xShmMap(file, 0, kRegion, 0, &region) != SQLITE_OK || region == nullptr)
    return false;
  base_ = static_cast<const volatile unsigned char*>(region);
  return true;
}

std::optional<WalIndexWatch::Header> WalIndexWatch::read() const {
  if (base_ == nullptr) return std::nullopt;
  // As SQLite's own readers do (walIndexTryHdr): the first copy, a barrier, the second; a writer
  // writes the second copy first, so equal copies are a whole header.
  Header first{}, second{};
  for (std::size_t i = 0; i < kCopy; ++i) first[i] = base_[i];
  std::atomic_thread_fence(std::memory_order_acquire);
  for (std::size_t i = 0; i < kCopy; ++i) second[i] = base_[kCopy + i];
  if (first != second || first[kIsInit] != 1) return std::nullopt;
  std::uint32_t version = 0;
  std::memcpy(&version, first.data(), sizeof version);
  if (version != kIndexVersion) return std::nullopt;
  return first;
}

}  // namespace flipper::naturalization
