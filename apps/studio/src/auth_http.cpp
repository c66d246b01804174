// Logins and logouts (auth_http.hpp, docs/accounts.md).
#include "auth_http.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "cookies.hpp"

namespace flipper::studio {
using Json = nlohmann::json;

int AuthEndpoints::login_wait_seconds(const std::string& address) {
  // Ten attempts per address per minute (each costs an Argon2id check: ~64 MiB, tens of ms).
  constexpr double kBurst = 10, kPerSecond = 10.0 / 60.0;
  std::lock_guard lock(login_mutex_);
  const auto now = std::chrono::steady_clock::now();
  auto [it, fresh] = login_buckets_.try_emplace(address, kBurst, now);
  auto& [tokens, refilled] = it->second;
  tokens =
      std::min(kBurst, tokens + std::chrono::duration<double>(now - refilled).count() * kPerSecond);
  refilled = now;
  if (tokens < 1.0) return static_cast<int>(std::ceil((1.0 - tokens) / kPerSecond));
  tokens -= 1.0;
  return 0;
}

void AuthEndpoints::login(const HttpRequest& r, const Respond& respond) {
  if (!hosts_.allows_origin(r))
    return respond(error_reply(403, "cross_origin", "logins must come from this server's page"));
  if (const int wait = login_wait_seconds(r.peer); wait > 0) {
    HttpReply refused = error_reply(429, "login_rate_limited",
                                    "too many login attempts from this address; wait a minute");
    refused.set_header("Retry-After", std::to_string(wait));
    return respond(refused);
  }
  auto job = [this, r, respond](int) {
    respond(answer_or_failure([&] { return login_reply(r); }));
  };
  if (!scheduler_.submit("login:" + r.peer, std::move(job)))
    respond(error_reply(429, "login_rate_limited", "too many login attempts waiting"));
}

HttpReply AuthEndpoints::login_reply(const HttpRequest& r) {
  const Json body = Json::parse(r.body, nullptr, false);
  if (!body.is_object())
    return error_reply(400, "bad_json", "send {\"name\", \"password\"} or {\"code\"}");
  const auto text = [&](const char* key) {
    return body.contains(key) && body[key].is_string() ? body[key].get<std::string>()
                                                       : std::string();
  };
  const auto valid_for = std::chrono::hours(24) * login_days_;
  std::optional<Login> login;
  if (!text("code").empty())
    login = accounts_.redeem(text("code"), valid_for);
  else if (!text("name").empty())
    login = accounts_.login(text("name"), text("password"), valid_for);
  else
    return error_reply(400, "missing_field", "send {\"name\", \"password\"} or {\"code\"}");
  if (!login)
    return error_reply(401, "bad_login",
                       "wrong name or password, or a code that is used, expired or unknown");
  HttpReply reply =
      json_reply(200, Json{{"ok", true}, {"user", login->name}, {"role", to_string(login->role)}});
  reply.set_header("Set-Cookie", login_cookie_header(login->token, valid_for));
  return reply;
}

void AuthEndpoints::logout(const HttpRequest& r, const Respond& respond) {
  if (!hosts_.allows_origin(r))
    return respond(error_reply(403, "cross_origin", "logouts must come from this server's page"));
  auto job = [this, r, respond](int) {
    respond(answer_or_failure([&] {
      const std::string token = login_cookie(r.cookie);
      if (!token.empty()) accounts_.logout(token);
      HttpReply reply = json_reply(200, Json{{"ok", true}});
      reply.set_header("Set-Cookie", login_cookie_cleared());
      return reply;
    }));
  };
  if (!scheduler_.submit("login:" + r.peer, std::move(job)))
    respond(error_reply(429, "session_busy", "too many requests waiting"));
}

}  // namespace flipper::studio
