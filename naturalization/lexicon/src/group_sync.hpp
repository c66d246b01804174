#pragma once
// Group commit (docs/naturalization.md §5 "Group commit"): the connections of one process on one
// store file commit with synchronous=NORMAL (the COMMIT writes the WAL frames, no sync) and then
// wait here until one fdatasync of the WAL, started after their COMMIT, has returned. The first
// waiter with no sync running leads: it syncs its own connection's WAL handle once for every
// commit registered so far; those that commit while it syncs wait and form the next batch. A
// failed sync fails every write of its batch with the sync's error, and every later write of
// this process too: the WAL is one chain, and recovery stops at the first frame that did not
// reach the disk, so nothing written after it can be acknowledged as durable.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace flipper::naturalization::sqlite {

class GroupSync {
 public:
  /// What a failed sync reports: the lexicon code and a message.
  struct Failure {
    std::string code;
    std::string message;
  };
  /// Syncs the caller's WAL; returns a Failure (code non-empty) when it did not.
  using SyncWal = std::function<Failure()>;

  /// Called right after a COMMIT returned: returns once a sync that started after this call
  /// returned; throws sdk::Error with the failure of that sync (or of an earlier failed one).
  void wait_durable(const SyncWal& sync_own_wal);

  /// Writes that waited here, and the syncs they shared (both since the process started).
  std::uint64_t writes() const;
  std::uint64_t syncs() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable synced_cv_;
  std::uint64_t committed_ = 0;  // tickets handed out (one per COMMIT)
  std::uint64_t synced_ = 0;     // every ticket <= synced_ is settled (durable or failed)
  bool syncing_ = false;
  std::uint64_t syncs_ = 0;
  std::uint64_t failed_from_ = 0;  // first ticket of the first failed batch (0: none)
  Failure failure_;
};

/// The GroupSync of the store file at `path` in this process (one per file, shared by every
/// connection opened on it while any holds it; keyed by the canonical path).
std::shared_ptr<GroupSync> group_sync_for(const std::string& path);
/// The one for `path` when a connection holds it, else null.
std::shared_ptr<GroupSync> find_group_sync(const std::string& path);

}  // namespace flipper::naturalization::sqlite
