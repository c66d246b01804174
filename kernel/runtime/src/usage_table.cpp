// UsageTable: a reader-writer locked map; reads (every scored induced node) far outnumber writes
// (one per accepted induced rule).
#include "flipper/kernel/usage_table.hpp"

#include <mutex>

namespace flipper::kernel {

sdk::RuleUses UsageTable::uses(const std::string& rule_id) const {
  const std::shared_lock lock(mutex_);
  const auto it = uses_.find(rule_id);
  return it == uses_.end() ? sdk::RuleUses{} : it->second;
}

void UsageTable::set(const std::string& rule_id, sdk::RuleUses uses) {
  const std::unique_lock lock(mutex_);
  uses_[rule_id] = uses;
}

void UsageTable::add(const std::string& rule_id, bool by_author, std::int64_t delta) {
  const std::unique_lock lock(mutex_);
  std::uint64_t& n = by_author ? uses_[rule_id].by_author : uses_[rule_id].by_others;
  n = static_cast<std::uint64_t>(static_cast<std::int64_t>(n) + delta);
}

void UsageTable::erase(const std::string& rule_id) {
  const std::unique_lock lock(mutex_);
  uses_.erase(rule_id);
}

}  // namespace flipper::kernel
