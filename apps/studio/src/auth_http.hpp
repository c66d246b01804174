#pragma once
// Logins (docs/accounts.md): the studio's authentication endpoints, apart from the protocol's
// (api.hpp), which only resumes the login a cookie names.
//   POST /api/v1/login {"name","password"} or {"code"}: a login cookie (ten attempts per address
//                       per minute: each costs an Argon2id check)
//   POST /api/v1/logout: ends the cookie's login
// Both come only from this server's page (same origin) and run on the scheduler's workers.
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <utility>

#include "flipper/studio/accounts.hpp"
#include "host_policy.hpp"
#include "http_types.hpp"
#include "scheduler.hpp"

namespace flipper::studio {

class AuthEndpoints {
 public:
  /// `login_days`: how long a login lasts (serve.login_days).
  AuthEndpoints(int login_days, AccountStore& accounts, Scheduler& scheduler,
                const HostPolicy& hosts)
      : login_days_(login_days), accounts_(accounts), scheduler_(scheduler), hosts_(hosts) {}

  void login(const HttpRequest& request, const Respond& respond);
  void logout(const HttpRequest& request, const Respond& respond);

 private:
  HttpReply login_reply(const HttpRequest& request);
  /// 0: a login from `address` may go on; else the seconds until it may (Retry-After).
  int login_wait_seconds(const std::string& address);

  int login_days_;
  AccountStore& accounts_;
  Scheduler& scheduler_;
  const HostPolicy& hosts_;
  std::mutex login_mutex_;
  std::map<std::string, std::pair<double, std::chrono::steady_clock::time_point>> login_buckets_;
};

}  // namespace flipper::studio
