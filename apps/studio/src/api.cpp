#include "api.hpp"

#include <malloc.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "cookies.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "recorder.hpp"
#include "studio_ops.hpp"
#include "study.hpp"

namespace flipper::studio {
using kernel::Json;

namespace {

constexpr double kTrimAfterMs = 50;  // requests this long may have grown the heap a lot

// Errors about the request's shape (the body is not a protocol request): HTTP 400. Every other
// answer, ok or not, is the session's answer: HTTP 200.
bool is_request_error(const std::string& code) {
  return code == "bad_json" || code == "unknown_op" || code == "missing_field" ||
         code == "bad_request";
}

}  // namespace

Api::Api(Sessions& sessions, ServeOptions options, AccountStore& accounts, Scheduler& scheduler,
         const HostPolicy& hosts)
    : sessions_(sessions),
      options_(std::move(options)),
      accounts_(accounts),
      scheduler_(scheduler),
      hosts_(hosts) {}

void Api::request(const HttpRequest& r, const Respond& respond) {
  if (!hosts_.allows_origin(r))
    return respond(error_reply(403, "cross_origin",
                               "state-changing requests must come from this server's own page "
                               "(Origin '" +
                                   r.origin.substr(0, 200) + "')"));
  const std::string token = r.param("session");
  // One request at a time per session. A request that opens a session is a key of its own (the
  // registry's per-address limits bound how many an address may open).
  const std::string key = token.empty() ? "new:" + std::to_string(++new_requests_) : token;
  // The session's group decides the pool; a new session goes to the pool of its group.
  std::shared_ptr<SessionEntry> entry = token.empty() ? nullptr : sessions_.registry().find(token);
  KernelPool& pool = sessions_.pools().pool_for(entry ? entry->group : r.param("group"));
  auto job = [this, r, respond, &pool](int worker) {
    respond(answer_or_failure(
        [&] { return serve(r, *pool.kernels[static_cast<std::size_t>(worker)]); }));
  };
  if (!pool.scheduler->submit(key, std::move(job)))
    respond(error_reply(429, "session_busy",
                        "this session already has requests waiting; send the next one after "
                        "the answer"));
}

HttpReply Api::serve(const HttpRequest& r, Kernel& k) {
  sessions_.bury_evicted();
  const auto now = Clock::now();
  const std::string token = r.param("session");
  const std::optional<Login> login = accounts_.resume(login_cookie(r.cookie));
  std::shared_ptr<SessionEntry> entry;
  HttpReply reply;
  if (!token.empty()) {
    entry = sessions_.registry().find(token);
    if (!entry)
      return error_reply(404, "unknown_session",
                         "no session has this token (it expired or the server restarted); send "
                         "the request without 'session' to start a new one");
    // An account's session is usable only with that account's login.
    if (!entry->account.empty() && (!login || login->name != entry->account))
      return error_reply(401, "login_required",
                         "this session belongs to account '" + entry->account +
                             "': log in as it (the login ended or was revoked)");
  } else {
    entry = sessions_.open(r, login, k, reply);
    if (!entry) return reply;
  }
  SessionRegistry& registry = sessions_.registry();
  if (!registry.admit(*entry, now))
    return error_reply(429, "rate_limited",
                       "too many requests in this session (serve.rate_per_second)");
  if (!registry.set_busy(*entry, true))
    return error_reply(429, "session_busy", "this session is answering another request");
  HttpReply out;
  try {
    out = run(*entry, k, r);
  } catch (...) {
    registry.set_busy(*entry, false);
    throw;
  }
  registry.set_busy(*entry, false);
  for (auto& [name, value] : reply.headers) out.set_header(name, value);  // a new login's cookie
  return out;
}

HttpReply Api::run(SessionEntry& entry, Kernel& free, const HttpRequest& r) {
  // A study's new session may run on a kernel of the pool the request named, not of the group
  // it was assigned: it stays on its own kernel then.
  Kernel& k = sessions_.pools().in_pool(entry.group, free) ? free : *entry.kernel;
  HttpReply reply;
  reply.set_header("Cache-Control", "no-store");
  reply.set_header("Flipper-Session", entry.token);
  reply.set_header("Flipper-User", header_safe(entry.user));
  // A study group that cannot learn (A, the core lexicon) is refused `define` before it
  // reaches the session, as the page offers no teaching there (docs/studio.md §7); not recorded.
  const std::shared_ptr<Recorder>& recorder = sessions_.recorder();
  if (recorder && entry.group == "A") {
    const Json request = Json::parse(r.body, nullptr, false);
    if (request.is_object() && request.value("op", std::string()) == "define") {
      reply.body = Json{{"ok", false},
                        {"op", "define"},
                        {"error",
                         {{"code", "teaching_off"},
                          {"message", "teaching new phrases is not part of this study"}}}}
                       .dump();
      return reply;
    }
  }
  kernel::Session& session = *entry.session;
  std::string answer;
  double ms = 0;
  StudioOps* ops = nullptr;
  {
    std::lock_guard lock(k.mutex);
    // The session moves to the kernel that is free (same config and store: it answers alike,
    // docs/studio.md §5).
    if (entry.kernel != &k) sessions_.move_to(entry, k);
    ops = session.extension<StudioOps>();
    session.activate();
    ops->reset();
    const auto start = Clock::now();
    answer = session.handle_line(r.body);
    ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    // Inside the kernel's lock: a group's records are in the order it answered (§5).
    if (recorder && !answer.empty() && recorder->record(entry, r.body, answer, ms).goal_reached)
      reply.set_header("Flipper-Goal", "reached");
  }
  // An expensive request (a long query builds large charts and traces) leaves the heap grown:
  // give the freed memory back to the system (docs/studio.md §4).
  if (ms >= kTrimAfterMs) malloc_trim(0);
  if (answer.empty()) {
    reply.status = 400;
    reply.body = error_body("bad_json", "the body is empty: send one request object");
    return reply;
  }
  if (answer.rfind("{\"ok\":false", 0) == 0) {
    // An op's refusal names its code; a request refused before any op ran (bad JSON, unknown op,
    // a line too long) is read back from the (short) error answer.
    std::string code = ops->error_code();
    if (!ops->op_ran()) {
      const Json a = Json::parse(answer, nullptr, false);
      if (a.is_object() && a.contains("error") && a["error"].is_object())
        code = a["error"].value("code", std::string());
    }
    reply.status = is_request_error(code) ? 400 : 200;
  }
  reply.body = std::move(answer);
  return reply;
}

void Api::info(const HttpRequest& r, const Respond& respond) {
  const std::string token = r.param("session");
  auto job = [this, r, respond](int) { respond(answer_or_failure([&] { return info_reply(r); })); };
  if (!scheduler_.submit(token.empty() ? "info:" + r.peer : token, std::move(job)))
    respond(error_reply(429, "session_busy", "too many requests waiting"));
}

HttpReply Api::info_reply(const HttpRequest& r) {
  const std::optional<Login> login = accounts_.resume(login_cookie(r.cookie));
  const std::string session = r.param("session");
  std::shared_ptr<SessionEntry> entry =
      session.empty() ? nullptr : sessions_.registry().find(session);
  Kernel& k = *sessions_.pools().pool_for(entry ? entry->group : std::string()).kernels.front();
  const kernel::Config& c = k.runtime->config;
  Json account = nullptr;
  if (login) account = Json{{"name", login->name}, {"role", to_string(login->role)}};
  // A study does not show its participants their condition (docs/studio.md §7).
  Json out{
      {"ok", true},
      {"sharing", sessions_.study()
                      ? Json()
                      : Json(naturalization::to_string(c.get(naturalization::keys::kSharing)))},
      {"k", c.get(kernel::keys::kSessionK)},
      {"max_chars", c.get(kernel::keys::kMaxChars)},
      {"vocabulary", k.vocabulary},
      {"worlds", k.worlds},
      {"account", account},
      {"guests", options_.guests},
      {"study", Json()}};
  if (const auto& study = sessions_.study()) {
    out["study"] = study->page_json();
    const auto& recorder = sessions_.recorder();
    if (entry && recorder)
      if (Json p = recorder->page_state(entry->participant); p.is_object()) out["study"].update(p);
  }
  return json_reply(200, out);
}

}  // namespace flipper::studio
