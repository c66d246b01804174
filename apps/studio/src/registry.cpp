#include "registry.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <random>

namespace flipper::studio {

std::string new_token() {
  static constexpr char kHex[] = "0123456789abcdef";
  std::random_device rd;  // /dev/urandom on Linux
  std::string out;
  for (int i = 0; i < 4; ++i) {
    std::uint32_t v = rd();
    for (int j = 0; j < 8; ++j, v >>= 4) out.push_back(kHex[v & 15]);
  }
  return out;
}

std::string subnet_of(const std::string& address) {
  in_addr v4{};
  if (inet_pton(AF_INET, address.c_str(), &v4) == 1) {
    const auto* b = reinterpret_cast<const unsigned char*>(&v4.s_addr);
    return std::to_string(b[0]) + "." + std::to_string(b[1]) + "." + std::to_string(b[2]) + ".0/24";
  }
  in6_addr v6{};
  if (inet_pton(AF_INET6, address.c_str(), &v6) != 1) return address;
  if (IN6_IS_ADDR_V4MAPPED(&v6))
    return std::to_string(v6.s6_addr[12]) + "." + std::to_string(v6.s6_addr[13]) + "." +
           std::to_string(v6.s6_addr[14]) + ".0/24";
  in6_addr prefix{};
  std::copy(v6.s6_addr, v6.s6_addr + 8, prefix.s6_addr);
  char text[INET6_ADDRSTRLEN] = {};
  inet_ntop(AF_INET6, &prefix, text, sizeof text);
  return std::string(text) + "/64";
}

std::shared_ptr<SessionEntry> SessionRegistry::find(const std::string& token) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(token);
  return it == sessions_.end() ? nullptr : it->second;
}

void SessionRegistry::erase_locked(
    std::map<std::string, std::shared_ptr<SessionEntry>>::iterator it) {
  SessionEntry& e = *it->second;
  used_bytes_ -= e.charged_bytes;
  e.charged_bytes = 0;
  if (e.account.empty()) {
    --guests_;
    if (auto a = per_address_.find(e.address); a != per_address_.end() && --a->second == 0)
      per_address_.erase(a);
    if (auto n = per_subnet_.find(subnet_of(e.address)); n != per_subnet_.end() && --n->second == 0)
      per_subnet_.erase(n);
  }
  evicted_.push_back(std::move(it->second));
  sessions_.erase(it);
}

template <class Enough>
bool SessionRegistry::evict_until(Clock::time_point now, std::chrono::seconds min_idle,
                                  Enough enough, bool guests_only) {
  if (enough()) return true;
  std::vector<std::pair<std::pair<bool, Clock::time_point>, std::string>> candidates;
  for (const auto& [token, e] : sessions_)
    if (!e->busy && now - e->last_used >= min_idle && (!guests_only || e->account.empty()))
      candidates.push_back({{!e->account.empty(), e->last_used}, token});  // guests first
  std::sort(candidates.begin(), candidates.end());
  for (const auto& c : candidates) {
    erase_locked(sessions_.find(c.second));
    if (enough()) return true;
  }
  return false;
}

namespace {

// Refills a token bucket holding at most `cap` at `per_minute`; a fresh bucket is full.
void refill(double& tokens, Clock::time_point& refilled, double cap, double per_minute,
            Clock::time_point now) {
  if (refilled == Clock::time_point()) tokens = cap;
  tokens = std::min(
      cap, tokens + std::chrono::duration<double>(now - refilled).count() * per_minute / 60.0);
  refilled = now;
}

}  // namespace

std::optional<SessionRegistry::Refusal> SessionRegistry::admit_new(const std::string& address,
                                                                   Clock::time_point now,
                                                                   bool account) {
  std::lock_guard lock(mutex_);
  Bucket& b = new_session_buckets_[address];
  refill(b.tokens, b.refilled, limits_.new_sessions_per_minute, limits_.new_sessions_per_minute,
         now);
  if (b.tokens < 1.0)
    return Refusal{429, "too_many_sessions",
                   "this address opens new sessions too fast "
                   "(serve.new_sessions_per_minute = " +
                       std::to_string(static_cast<long>(limits_.new_sessions_per_minute)) +
                       "); keep using the session you have"};
  if (!account) {
    if (auto a = per_address_.find(address);
        a != per_address_.end() && a->second >= limits_.sessions_per_address)
      return Refusal{429, "too_many_sessions",
                     "this address holds " + std::to_string(a->second) +
                         " sessions (serve.sessions_per_address); keep using the ones you have"};
    const std::string subnet = subnet_of(address);
    if (auto n = per_subnet_.find(subnet);
        n != per_subnet_.end() && n->second >= limits_.sessions_per_subnet)
      return Refusal{429, "too_many_sessions",
                     "the addresses of " + subnet + " hold " + std::to_string(n->second) +
                         " guest sessions (serve.sessions_per_subnet); log in, or keep using "
                         "the sessions you have"};
    refill(new_guests_.tokens, new_guests_.refilled, limits_.new_guests_per_minute,
           limits_.new_guests_per_minute, now);
    if (new_guests_.tokens < 1.0)
      return Refusal{503, "too_many_sessions",
                     "the server opens at most " +
                         std::to_string(static_cast<long>(limits_.new_guests_per_minute)) +
                         " guest sessions a minute (serve.new_guests_per_minute); try again "
                         "shortly, or log in"};
  }
  // Guests may hold all but the reserved sessions; accounts all of them. Idle guests make room
  // first (after serve.evict_after_s), then any session idle for serve.session_idle_s.
  const std::size_t reserved = limits_.max_sessions * limits_.reserved_percent / 100;
  const std::size_t guest_cap = limits_.max_sessions - reserved;
  const auto room = [&] {
    return sessions_.size() < limits_.max_sessions && (account || guests_ < guest_cap) &&
           used_bytes_ + limits_.session_base_bytes <= limits_.memory_budget_bytes;
  };
  const bool guests_full = !account && guests_ >= guest_cap;
  bool ok = evict_until(now, limits_.evict_after, room, true) ||
            evict_until(now, limits_.idle, room, guests_full);
  if (!ok && sessions_.size() >= limits_.max_sessions)
    return Refusal{503, "too_many_sessions",
                   "the server has " + std::to_string(sessions_.size()) +
                       " sessions (serve.max_sessions); try later"};
  if (!ok && guests_full)
    return Refusal{503, "too_many_sessions",
                   "the server has " + std::to_string(guests_) + " guest sessions; the other " +
                       std::to_string(reserved) +
                       " are kept for logged-in users (serve.reserved_sessions_percent); log "
                       "in, or try later"};
  if (!ok)
    return Refusal{503, "server_busy",
                   "the server's memory for sessions is in use (" +
                       std::to_string(limits_.memory_budget_bytes >> 20) +
                       " MiB: serve.memory_budget_mb less the kernels'); try later"};
  b.tokens -= 1.0;
  if (!account) new_guests_.tokens -= 1.0;
  return std::nullopt;
}

std::shared_ptr<SessionEntry> SessionRegistry::add(std::shared_ptr<SessionEntry> entry,
                                                   Clock::time_point now) {
  std::lock_guard lock(mutex_);
  std::string token = new_token();
  while (sessions_.count(token)) token = new_token();
  entry->token = token;
  entry->last_used = now;
  entry->bucket = limits_.rate_burst;
  entry->refilled = now;
  entry->charged_bytes = limits_.session_base_bytes;
  used_bytes_ += entry->charged_bytes;
  if (entry->account.empty()) {
    ++guests_;
    ++per_address_[entry->address];
    ++per_subnet_[subnet_of(entry->address)];
  }
  sessions_[token] = entry;
  return entry;
}

bool SessionRegistry::admit(SessionEntry& e, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const double elapsed = std::chrono::duration<double>(now - e.refilled).count();
  // Idle time refills the bucket up to the burst, never beyond.
  e.bucket = std::min(limits_.rate_burst, e.bucket + elapsed * limits_.rate_per_second);
  e.refilled = now;
  e.last_used = now;
  if (e.bucket < 1.0) return false;
  e.bucket -= 1.0;
  return true;
}

bool SessionRegistry::set_busy(SessionEntry& e, bool busy) {
  std::lock_guard lock(mutex_);
  if (busy && e.busy) return false;
  e.busy = busy;
  e.last_used = Clock::now();
  return true;
}

bool SessionRegistry::reserve(SessionEntry& e, std::size_t bytes, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const bool ok = evict_until(
      now, limits_.evict_after, [&] { return used_bytes_ + bytes <= limits_.memory_budget_bytes; },
      false);
  if (!ok) return false;
  used_bytes_ += bytes;
  e.charged_bytes += bytes;
  return true;
}

void SessionRegistry::charge(SessionEntry& e, std::size_t bytes) {
  std::lock_guard lock(mutex_);
  if (!sessions_.count(e.token)) return;  // evicted meanwhile: nothing is charged any more
  used_bytes_ = used_bytes_ - e.charged_bytes + bytes;
  e.charged_bytes = bytes;
}

std::size_t SessionRegistry::used_bytes() const {
  std::lock_guard lock(mutex_);
  return used_bytes_;
}

std::size_t SessionRegistry::size() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

std::vector<std::shared_ptr<SessionEntry>> SessionRegistry::take_evicted() {
  std::lock_guard lock(mutex_);
  return std::exchange(evicted_, {});
}

}  // namespace flipper::studio
