#include "registry.hpp"

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

SessionEntry* SessionRegistry::find(const std::string& token) {
  auto it = sessions_.find(token);
  return it == sessions_.end() ? nullptr : &it->second;
}

void SessionRegistry::evict_idle(Clock::time_point now) {
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (now - it->second.last_used < limits_.idle) {
      ++it;
      continue;
    }
    // The evicted session's user names become free again.
    for (auto o = owners_.begin(); o != owners_.end();)
      o = o->second == it->first ? owners_.erase(o) : std::next(o);
    it = sessions_.erase(it);
  }
}

SessionEntry* SessionRegistry::add(std::unique_ptr<kernel::Session> session,
                                   Clock::time_point now) {
  if (sessions_.size() >= limits_.max_sessions) evict_idle(now);
  if (sessions_.size() >= limits_.max_sessions) return nullptr;
  std::string token = new_token();
  while (sessions_.count(token)) token = new_token();
  const std::string guest = "guest-" + std::to_string(++guests_);
  session->set_user(guest);
  owners_[guest] = token;
  SessionEntry& e = sessions_[token];
  e.token = token;
  e.session = std::move(session);
  e.last_used = now;
  e.bucket = limits_.rate_burst;
  e.refilled = now;
  return &e;
}

bool SessionRegistry::admit(SessionEntry& e, Clock::time_point now) {
  const double elapsed = std::chrono::duration<double>(now - e.refilled).count();
  e.bucket = std::min(limits_.rate_burst, e.bucket + elapsed * limits_.rate_per_second);
  e.refilled = now;
  e.last_used = now;
  if (e.bucket < 1.0) return false;
  e.bucket -= 1.0;
  return true;
}

bool SessionRegistry::claim_user(const std::string& name, const std::string& token) {
  // Names under "sempre:" are /sempre's sessionIds (docs/sempre.md): never an /api/v1 user.
  if (name.rfind("sempre:", 0) == 0) return false;
  auto [it, inserted] = owners_.emplace(name, token);
  // "guest-N" names are only ever given by add(); an unclaimed one is not up for grabs.
  if (inserted && name.rfind("guest-", 0) == 0) {
    owners_.erase(it);
    return false;
  }
  return it->second == token;
}

}  // namespace flipper::studio
