#pragma once
// The server's protocol sessions, keyed by unguessable tokens the server issues (128 random
// bits): a client acts only in sessions whose token it was given. Each session's user is fixed
// when it is opened: the account that was logged in, or a guest name (docs/accounts.md). The
// registry also keeps the limits that protect everyone from one client (docs/studio.md §4):
// open sessions in total and per address, new sessions per address per minute, requests per
// session (token bucket), and the memory budget for session state, reclaimed by evicting idle
// sessions, guests first. Thread-safe.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/session.hpp"
#include "flipper/studio/accounts.hpp"

namespace flipper::studio {

using Clock = std::chrono::steady_clock;
struct Kernel;

struct SessionEntry {
  std::string token;
  std::unique_ptr<kernel::Session> session;
  Kernel* kernel = nullptr;
  std::string user;     ///< the session's user: the account's name or "guest-N"
  std::string account;  ///< "" for a guest
  Role role = Role::user;
  std::string login;        ///< the login token that opened it ("" for a guest)
  std::string address;      ///< the client address that opened it
  std::string group;        ///< study mode: the participant's group ("" otherwise)
  std::string participant;  ///< study mode: the participant's id
  // Guarded by the registry's mutex:
  Clock::time_point last_used;
  double bucket = 0;  ///< rate-limit tokens left
  Clock::time_point refilled;
  std::size_t charged_bytes = 0;  ///< of the memory budget
  bool busy = false;              ///< a request is running: never evicted
};

struct RegistryLimits {
  std::size_t max_sessions = 1000;
  std::chrono::seconds idle{3600};  ///< idle sessions may be evicted when the server is full
  double rate_per_second = 100;
  double rate_burst = 200;
  std::size_t sessions_per_address = 32;
  double new_sessions_per_minute = 60;  ///< per address (token bucket, this many banked)
  std::size_t memory_budget_bytes = std::size_t{1} << 30;
  std::size_t session_base_bytes = std::size_t{64} * 1024;  ///< charged for every open session
  std::chrono::seconds evict_after{120};  ///< idle time after which the budget may evict
  // Admission from many addresses (docs/studio.md §4 "Admission"); guests only: an account is
  // authenticated, and a lab's participants may share one address.
  std::size_t sessions_per_subnet = 128;  ///< guests per /24 (IPv4) or /64 (IPv6)
  double new_guests_per_minute = 600;     ///< new guest sessions, all addresses together
  std::size_t reserved_percent = 10;      ///< of max_sessions, kept for accounts
};

/// The subnet an address is counted in: "a.b.c/24" for IPv4 (and IPv4-mapped IPv6), the first
/// 64 bits for IPv6 ("2001:db8:0:1::/64"); the address itself when it is neither.
std::string subnet_of(const std::string& address);

class SessionRegistry {
 public:
  explicit SessionRegistry(RegistryLimits limits) : limits_(limits) {}

  std::shared_ptr<SessionEntry> find(const std::string& token);

  /// Why a new session for `address` cannot be opened now, after evicting idle sessions when
  /// the server is full; nullopt when it can. `account`: the session is a logged-in account's
  /// (it may use the reserved sessions; the per-address, per-subnet and guest-rate limits are
  /// for guests).
  struct Refusal {
    int status;  ///< 429: this address asks too much; 503: the server is full
    std::string code, message;
  };
  std::optional<Refusal> admit_new(const std::string& address, Clock::time_point now,
                                   bool account = false);
  /// Adds a session (call admit_new first) under a fresh token.
  std::shared_ptr<SessionEntry> add(std::shared_ptr<SessionEntry> entry, Clock::time_point now);
  /// Takes one request from the entry's token bucket; false when the rate is exceeded.
  bool admit(SessionEntry& entry, Clock::time_point now);
  /// Marks the entry running (true) or done; an entry already running is refused (false).
  bool set_busy(SessionEntry& entry, bool busy);

  /// Reserves `bytes` of the memory budget for `entry` (a world about to load), evicting idle
  /// sessions (guests first, the longest idle first) when needed; false when the budget cannot
  /// hold it.
  bool reserve(SessionEntry& entry, std::size_t bytes, Clock::time_point now);
  /// Sets what the entry holds after the load (returns the rest of a reservation).
  void charge(SessionEntry& entry, std::size_t bytes);
  std::size_t used_bytes() const;
  std::size_t size() const;
  /// Sessions evicted since the last call; the caller destroys them under their kernel's lock.
  std::vector<std::shared_ptr<SessionEntry>> take_evicted();

  const RegistryLimits& limits() const { return limits_; }
  /// Sets the memory for session state (the budget less the kernels', known once they loaded).
  void set_memory_budget(std::size_t bytes) {
    std::lock_guard lock(mutex_);
    limits_.memory_budget_bytes = bytes;
  }

 private:
  void erase_locked(std::map<std::string, std::shared_ptr<SessionEntry>>::iterator it);
  /// Evicts idle entries (not busy, idle >= min_idle; guests only when `guests_only`), guests
  /// first, oldest first, until `enough()` holds; returns whether it does.
  template <class Enough>
  bool evict_until(Clock::time_point now, std::chrono::seconds min_idle, Enough enough,
                   bool guests_only);

  RegistryLimits limits_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<SessionEntry>> sessions_;
  std::map<std::string, std::size_t> per_address_;  ///< open guest sessions
  std::map<std::string, std::size_t> per_subnet_;   ///< open guest sessions
  std::size_t guests_ = 0;                          ///< open guest sessions in total
  struct Bucket {
    double tokens = 0;
    Clock::time_point refilled;
  };
  std::map<std::string, Bucket> new_session_buckets_;
  Bucket new_guests_;  ///< all addresses together
  std::size_t used_bytes_ = 0;
  std::vector<std::shared_ptr<SessionEntry>> evicted_;
};

/// 32 hex digits from the system's random source.
std::string new_token();

}  // namespace flipper::studio
