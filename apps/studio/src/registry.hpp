#pragma once
// The server's sessions, keyed by unguessable tokens the server issues (128 random bits): a
// client can act only in sessions whose token it was given. User names are claimed by the first
// session that takes them, so one session cannot act as another session's user (define as them,
// delete their rules). Not thread-safe: the API serialises every call.
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "flipper/kernel/session.hpp"

namespace flipper::studio {

using Clock = std::chrono::steady_clock;

struct SessionEntry {
  std::string token;
  std::unique_ptr<kernel::Session> session;
  Clock::time_point last_used;
  double bucket = 0;  ///< rate-limit tokens left
  Clock::time_point refilled;
  std::string group;        ///< study mode: the participant's group ("" otherwise)
  std::string participant;  ///< study mode: the participant's id
};

struct RegistryLimits {
  std::size_t max_sessions = 1000;
  std::chrono::seconds idle{3600};
  double rate_per_second = 100;
  double rate_burst = 200;
};

class SessionRegistry {
 public:
  explicit SessionRegistry(RegistryLimits limits) : limits_(limits) {}

  SessionEntry* find(const std::string& token);
  /// Adds a session under a fresh token and its own guest user ("guest-N", claimed). Evicts
  /// sessions idle longer than the limit when full; returns null when still full.
  SessionEntry* add(std::unique_ptr<kernel::Session> session, Clock::time_point now);
  /// Takes one request from the entry's token bucket; false when the rate is exceeded.
  bool admit(SessionEntry& entry, Clock::time_point now);
  /// Whether `token`'s session may become user `name`: unclaimed names are claimed for it.
  bool claim_user(const std::string& name, const std::string& token);
  std::size_t size() const { return sessions_.size(); }

 private:
  void evict_idle(Clock::time_point now);
  RegistryLimits limits_;
  std::map<std::string, SessionEntry> sessions_;
  std::map<std::string, std::string> owners_;  ///< user name -> token
  std::uint64_t guests_ = 0;
};

/// 32 hex digits from the system's random source.
std::string new_token();

}  // namespace flipper::studio
