// Group commit across the connections of one process (group_sync.hpp; docs/naturalization.md §5).
#include "group_sync.hpp"

#include <filesystem>
#include <map>

#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization::sqlite {

void GroupSync::wait_durable(const SyncWal& sync_own_wal) {
  std::unique_lock<std::mutex> lock(mutex_);
  // The COMMIT returned before this ticket was taken, so a sync started after it covers it.
  const std::uint64_t ticket = ++committed_;
  if (failed_from_ != 0) throw sdk::Error(failure_.code, failure_.message);
  while (synced_ < ticket) {
    if (syncing_) {
      synced_cv_.wait(lock);
      continue;
    }
    // Lead: one sync for every commit registered so far.
    syncing_ = true;
    const std::uint64_t batch_end = committed_;
    lock.unlock();
    Failure failure;
    try {
      failure = sync_own_wal();
    } catch (const std::exception& e) {
      failure = {"bad_lexicon", e.what()};
    }
    lock.lock();
    ++syncs_;
    if (!failure.code.empty() && failed_from_ == 0) {
      failed_from_ = synced_ + 1;
      failure_ = std::move(failure);
    }
    synced_ = batch_end;
    syncing_ = false;
    synced_cv_.notify_all();
  }
  if (failed_from_ != 0 && ticket >= failed_from_)
    throw sdk::Error(failure_.code, failure_.message);
}

std::uint64_t GroupSync::writes() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return committed_;
}

std::uint64_t GroupSync::syncs() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return syncs_;
}

namespace {

std::mutex registry_mutex;
std::map<std::string, std::weak_ptr<GroupSync>>& registry() {
  static std::map<std::string, std::weak_ptr<GroupSync>> r;
  return r;
}

std::string key_of(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  return ec ? path : canonical.string();
}

}  // namespace

std::shared_ptr<GroupSync> group_sync_for(const std::string& path) {
  const std::lock_guard<std::mutex> lock(registry_mutex);
  std::weak_ptr<GroupSync>& slot = registry()[key_of(path)];
  std::shared_ptr<GroupSync> sync = slot.lock();
  if (!sync) {
    sync = std::make_shared<GroupSync>();
    slot = sync;
  }
  return sync;
}

std::shared_ptr<GroupSync> find_group_sync(const std::string& path) {
  const std::lock_guard<std::mutex> lock(registry_mutex);
  const auto it = registry().find(key_of(path));
  return it == registry().end() ? nullptr : it->second.lock();
}

}  // namespace flipper::naturalization::sqlite
