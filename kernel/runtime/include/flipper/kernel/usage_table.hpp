#pragma once
/// @file usage_table.hpp
/// The kernel's use counters of induced rules (docs/naturalization.md §5): how often a
/// candidate built with a rule was accepted, by its author and by others. The session counts
/// accepts here, naturalization restores and persists them, and scorers read them through
/// sdk::ScoreContext::usage; a rule itself stays immutable once shared. One table per runtime,
/// shared by all its sessions (thread-safe).

#include <cstdint>
#include <shared_mutex>
#include <string>
#include <unordered_map>

#include "flipper/sdk/scorer.hpp"
#include "flipper/toolkit/process/child_call.hpp"

namespace flipper::kernel {

class UsageTable final : public sdk::UsageCounters {
 public:
  sdk::RuleUses uses(const std::string& rule_id) const override;
  /// Replaces a rule's counts (restored from the lexicon store).
  void set(const std::string& rule_id, sdk::RuleUses uses);
  /// Adds `delta` (+1 on accept, -1 to undo one) to the author's or the others' count.
  void add(const std::string& rule_id, bool by_author, std::int64_t delta);
  void erase(const std::string& rule_id);

 private:
  mutable std::shared_mutex mutex_;
  // Isolated parses read the table in a child process (isolation.hpp).
  toolkit::process::ReadAcrossFork fork_guard_{mutex_};
  std::unordered_map<std::string, sdk::RuleUses> uses_;
};

}  // namespace flipper::kernel
