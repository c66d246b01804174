#include "api.hpp"

#include <malloc.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "cookies.hpp"
#include "enrolment.hpp"
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

RegistryLimits registry_limits(const ServeOptions& o) {
  RegistryLimits l{o.max_sessions,
                   std::chrono::seconds(o.session_idle_s),
                   o.rate_per_second,
                   o.rate_burst,
                   o.sessions_per_address,
                   static_cast<double>(o.new_sessions_per_minute),
                   o.memory_budget_mb << 20,
                   std::size_t{64} * 1024,
                   std::chrono::seconds(o.evict_after_s)};
  l.sessions_per_subnet = o.sessions_per_subnet;
  l.new_guests_per_minute = static_cast<double>(o.new_guests_per_minute);
  l.reserved_percent = o.reserved_sessions_percent;
  return l;
}

}  // namespace

Api::Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options,
         AccountStore& accounts, Scheduler& scheduler, const HostPolicy& hosts)
    : options_(std::move(options)),
      accounts_(accounts),
      scheduler_(scheduler),
      hosts_(hosts),
      pools_(kernels, options_),
      registry_(registry_limits(options_)) {
  registry_.set_memory_budget(pools_.session_budget(options_));
}

Api::~Api() {
  pools_.stop_workers();  // their workers use the sessions
  bury_evicted();
  for (auto& e : graves_) e->session.reset();  // no worker runs any more
}

void Api::bury_evicted() {
  std::lock_guard graves(graves_mutex_);
  for (auto& e : registry_.take_evicted()) graves_.push_back(std::move(e));
  std::erase_if(graves_, [](const std::shared_ptr<SessionEntry>& e) {
    if (e->kernel == nullptr || !e->session) return true;
    std::unique_lock lock(e->kernel->mutex, std::try_to_lock);
    if (!lock.owns_lock()) return false;  // its kernel is answering: a later call buries it
    e->session.reset();
    return true;
  });
}

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
  std::shared_ptr<SessionEntry> entry = token.empty() ? nullptr : registry_.find(token);
  KernelPool& pool = pools_.pool_for(entry ? entry->group : r.param("group"));
  auto job = [this, r, respond, &pool](int worker) {
    respond(answer_or_failure(
        [&] { return serve(r, *pool.kernels[static_cast<std::size_t>(worker)]); }));
  };
  if (!pool.scheduler->submit(key, std::move(job)))
    respond(error_reply(429, "session_busy",
                        "this session already has requests waiting; send the next one after "
                        "the answer"));
}

void Api::run_on_plain_kernel(const std::string& key, std::function<HttpReply()> job,
                              const Respond& respond) {
  // Pinned to the first kernel: /sempre keeps its sessions there (docs/sempre.md).
  auto work = [job = std::move(job), respond](int) { respond(answer_or_failure(job)); };
  if (!pools_.pool_for(std::string()).scheduler->submit(key, std::move(work), 0))
    respond(error_reply(429, "session_busy",
                        "this session already has requests waiting; send the next one after "
                        "the answer"));
}

HttpReply Api::serve(const HttpRequest& r, Kernel& k) {
  bury_evicted();
  const auto now = Clock::now();
  const std::string token = r.param("session");
  const std::optional<Login> login = accounts_.resume(login_cookie(r.cookie));
  std::shared_ptr<SessionEntry> entry;
  HttpReply reply;
  if (!token.empty()) {
    entry = registry_.find(token);
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
    entry = open_session(r, login, k, reply);
    if (!entry) return reply;
  }
  if (!registry_.admit(*entry, now))
    return error_reply(429, "rate_limited",
                       "too many requests in this session (serve.rate_per_second)");
  if (!registry_.set_busy(*entry, true))
    return error_reply(429, "session_busy", "this session is answering another request");
  HttpReply out;
  try {
    out = run(*entry, k, r);
  } catch (...) {
    registry_.set_busy(*entry, false);
    throw;
  }
  registry_.set_busy(*entry, false);
  for (auto& [name, value] : reply.headers) out.set_header(name, value);  // a new login's cookie
  return out;
}

std::shared_ptr<SessionEntry> Api::open_session(const HttpRequest& r,
                                                const std::optional<Login>& login, Kernel& k,
                                                HttpReply& reply) {
  if (!login && !options_.guests) {
    reply = error_reply(401, "login_required",
                        "this server has no guests (serve.guests: false): log in first");
    return nullptr;
  }
  if (auto refused = registry_.admit_new(r.peer, Clock::now(), login.has_value())) {
    reply = error_reply(refused->status, refused->code, refused->message);
    return nullptr;
  }
  auto entry = std::make_shared<SessionEntry>();
  entry->address = r.peer;
  std::string group = r.param("group");
  bool resumed = false;
  std::optional<Login> who = login;
  if (recorder_ && !enroll(*recorder_, accounts_, options_, r, who, *entry, resumed, reply))
    return nullptr;
  if (who) {
    entry->user = who->name;
    entry->account = who->name;
    entry->role = who->role;
    entry->login = who->token;
  } else {
    entry->user = accounts_.next_guest();
  }
  if (recorder_) group = entry->group;
  entry->group = group;
  // A study may assign another group than the request named: the session opens on that pool's
  // first kernel and moves to a free one of its pool from its next request on.
  Kernel& at = pools_.in_pool(group, k) ? k : *pools_.pool_for(group).kernels.front();
  entry->kernel = &at;
  {
    std::lock_guard lock(at.mutex);
    entry->session = at.host->open();
    entry->session->set_user(entry->user);
    install_studio_ops(*entry, at);
  }
  registry_.add(entry, Clock::now());
  if (recorder_) {
    std::lock_guard lock(at.mutex);
    recorder_->session_started(*entry, resumed);
    if (resumed) resume_world(*recorder_, *entry);
  }
  return entry;
}

void Api::install_studio_ops(SessionEntry& entry, Kernel& k) {
  StudioOpsContext ctx;
  ctx.world_root = k.world_root;
  ctx.role = entry.role;
  ctx.max_world_bytes = k.max_world_bytes;
  ctx.budget_bytes = options_.memory_budget_mb << 20;
  SessionEntry* raw = &entry;
  const std::size_t base = registry_.limits().session_base_bytes;
  ctx.reserve = [this, raw](std::size_t bytes) {
    return registry_.reserve(*raw, bytes, Clock::now());
  };
  ctx.charge = [this, raw, base](std::size_t bytes) { registry_.charge(*raw, base + bytes); };
  entry.session->install(std::make_shared<StudioOps>(std::move(ctx)));
  if (recorder_) entry.session->install(std::make_shared<RecorderTap>());  // what it records
}

void Api::install_ops(SessionEntry& entry, Kernel& k) {
  entry.session->rebind(k.runtime, k.host->extensions);  // the studio's ops come along
  entry.kernel = &k;
}

HttpReply Api::run(SessionEntry& entry, Kernel& free, const HttpRequest& r) {
  // A study's new session may run on a kernel of the pool the request named, not of the group
  // it was assigned: it stays on its own kernel then.
  Kernel& k = pools_.in_pool(entry.group, free) ? free : *entry.kernel;
  HttpReply reply;
  reply.set_header("Cache-Control", "no-store");
  reply.set_header("Flipper-Session", entry.token);
  reply.set_header("Flipper-User", header_safe(entry.user));
  // A study group that cannot learn (A, the core lexicon) is refused `define` before it
  // reaches the session, as the page offers no teaching there (docs/studio.md §7); not recorded.
  if (recorder_ && entry.group == "A") {
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
    if (entry.kernel != &k) install_ops(entry, k);
    ops = session.extension<StudioOps>();
    session.activate();
    ops->reset();
    const auto start = Clock::now();
    answer = session.handle_line(r.body);
    ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    // Inside the kernel's lock: a group's records are in the order it answered (§5).
    if (recorder_ && !answer.empty() && recorder_->record(entry, r.body, answer, ms).goal_reached)
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
  std::shared_ptr<SessionEntry> entry = session.empty() ? nullptr : registry_.find(session);
  Kernel& k = *pools_.pool_for(entry ? entry->group : std::string()).kernels.front();
  const kernel::Config& c = k.runtime->config;
  Json account = nullptr;
  if (login) account = Json{{"name", login->name}, {"role", to_string(login->role)}};
  // A study does not show its participants their condition (docs/studio.md §7).
  Json out{
      {"ok", true},
      {"sharing",
       study_ ? Json() : Json(naturalization::to_string(c.get(naturalization::keys::kSharing)))},
      {"k", c.get(kernel::keys::kSessionK)},
      {"max_chars", c.get(kernel::keys::kMaxChars)},
      {"vocabulary", k.vocabulary},
      {"worlds", k.worlds},
      {"account", account},
      {"guests", options_.guests},
      {"study", Json()}};
  if (study_) {
    out["study"] = study_->page_json();
    if (entry && recorder_)
      if (Json p = recorder_->page_state(entry->participant); p.is_object()) out["study"].update(p);
  }
  return json_reply(200, out);
}

}  // namespace flipper::studio
