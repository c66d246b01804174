#include "api.hpp"

#include <malloc.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "recorder.hpp"
#include "studio_ops.hpp"
#include "study.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;

namespace {

constexpr const char* kCookie = "flipper_login";
constexpr double kTrimAfterMs = 50;  // requests this long may have grown the heap a lot

// Errors about the request's shape (the body is not a protocol request): HTTP 400. Every other
// answer, ok or not, is the session's answer: HTTP 200.
bool is_request_error(const std::string& code) {
  return code == "bad_json" || code == "unknown_op" || code == "missing_field" ||
         code == "bad_request";
}

// Every token of the core grammar plus its word classes: the vocabulary for "did you mean".
Json vocabulary(const kernel::Runtime& rt) {
  std::set<std::string> words;
  if (rt.core_grammar) {
    for (const auto& rule : rt.core_grammar->rules)
      for (const auto& s : rule->rhs)
        if (s.type == sdk::Symbol::Type::token) words.insert(s.text);
    for (const auto* list :
         {&rt.core_grammar->colors, &rt.core_grammar->shapes, &rt.core_grammar->directions})
      words.insert(list->begin(), list->end());
  }
  return Json(std::vector<std::string>(words.begin(), words.end()));
}

// The world menu (docs/studio.md "The page"): the *.json files of the config's world directory
// that this runtime's world plugin loads (a 3-D world is no choice on a 2-D server), each read
// within input.max_file_bytes and world.max_cells as a `world` request would be.
Json world_files(const kernel::Runtime& rt, const std::string& root) {
  Json out = Json::array();
  std::error_code ec;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(root, ec))
    if (e.is_regular_file() && e.path().extension() == ".json")
      names.insert(e.path().filename().string());
  for (const auto& n : names) {
    try {
      (void)kernel::load_world_file(rt, (fs::path(root) / n).string());
      out.push_back(n);
    } catch (const std::exception&) {
      // not a world of this runtime: left out of the menu
    }
  }
  return out;
}

// serve.kernels: 0 means the cores plus one kernel the heavy sessions cannot take. A store in
// memory is private to its connection: one kernel then.
// A study group has one kernel: its records are then in the order it answered, and a replay
// of them meets the same store (docs/studio.md §5).
int pool_size(const ServeOptions& options, const kernel::Config& config) {
  if (config.text(naturalization::keys::kLexiconPath) == ":memory:" || !options.study.empty())
    return 1;
  if (options.kernels > 0) return options.kernels;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) + 1;
}

// Heavy sessions may hold this many kernels at once: one core's worth less than the machine has,
// so a cheap request finds a free kernel and a free core (with every core busy with heavy
// queries, `move left` waited for the CPU: p99 up to 250 ms, against 5 ms; docs/studio.md §5).
int heavy_kernels(int kernels) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return kernels > 1 ? std::max(1, std::min(kernels - 1, cores - 1)) : 1;
}

// What the kernels leave of the memory budget for sessions; bad_config when they would take
// more than half of it.
std::size_t session_budget(const ServeOptions& options, std::size_t kernels,
                           std::size_t kernels_bytes) {
  const std::size_t budget = options.memory_budget_mb << 20;
  if (kernels_bytes * 2 > budget)
    throw sdk::Error(sdk::codes::kBadConfig,
                     std::to_string(kernels) + " kernels take " +
                         std::to_string((kernels_bytes + (1 << 20) - 1) >> 20) +
                         " MiB, more than half of serve.memory_budget_mb (" +
                         std::to_string(options.memory_budget_mb) +
                         " MiB): lower serve.kernels or raise the budget");
  return budget - kernels_bytes;
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

std::size_t kernel_bytes(std::size_t rules) {
  return (std::size_t{4} << 20) + rules * 1024;
}

namespace {}  // namespace

std::string login_cookie(const std::string& header) {
  // "a=1; flipper_login=TOKEN; b=2"
  std::size_t at = 0;
  while (at < header.size()) {
    while (at < header.size() && (header[at] == ' ' || header[at] == ';')) ++at;
    const auto end = header.find(';', at);
    const std::string pair = header.substr(at, end == std::string::npos ? end : end - at);
    const auto eq = pair.find('=');
    if (eq != std::string::npos && pair.substr(0, eq) == kCookie) return pair.substr(eq + 1);
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return {};
}

std::string login_cookie_header(const std::string& token, std::chrono::seconds valid_for) {
  return std::string(kCookie) + "=" + token +
         "; Path=/; HttpOnly; SameSite=Strict; Max-Age=" + std::to_string(valid_for.count());
}

std::string header_safe(const std::string& name) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '.' || c == '_' || c == '-') {
      out.push_back(c);
    } else {
      out.push_back('%');
      out.push_back(kHex[u >> 4]);
      out.push_back(kHex[u & 15]);
    }
  }
  return out;
}

Api::Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options,
         AccountStore& accounts, Scheduler& scheduler, const HostPolicy& hosts)
    : options_(std::move(options)),
      accounts_(accounts),
      scheduler_(scheduler),
      hosts_(hosts),
      registry_(registry_limits(options_)) {
  std::size_t count = 0, bytes = 0;
  for (const auto& [group, config] : kernels) {
    KernelPool& pool = pools_[group];
    const int n = pool_size(options_, config);
    for (int i = 0; i < n; ++i) {
      auto k = std::make_unique<Kernel>();
      k->runtime = kernel::make_runtime(config);
      k->host = std::make_unique<wiring::SessionHost>(wiring::open_host(k->runtime));
      std::error_code ec;
      k->world_root =
          fs::weakly_canonical(fs::path(config.get(kernel::keys::kWorldFile)).parent_path(), ec)
              .string();
      k->max_world_bytes =
          world_bytes(static_cast<std::size_t>(config.get(kernel::keys::kMaxWorldCells)));
      k->vocabulary = vocabulary(*k->runtime);
      k->worlds = pool.kernels.empty() ? world_files(*k->runtime, k->world_root)
                                       : pool.kernels.front()->worlds;
      bytes += kernel_bytes(k->host->naturalizer->induced_rules().size());
      ++count;
      pool.kernels.push_back(std::move(k));
    }
    SchedulerOptions so;
    so.workers = n;
    so.reserve = n - heavy_kernels(n);
    so.cpu_ms_per_s = options_.cpu_ms_per_s;
    so.cpu_burst_ms = options_.cpu_burst_ms;
    pool.scheduler = std::make_unique<Scheduler>(so);
  }
  registry_.set_memory_budget(session_budget(options_, count, bytes));
}

Api::~Api() {
  for (auto& [group, pool] : pools_) pool.scheduler.reset();  // their workers use the sessions
  bury_evicted();
  for (auto& e : graves_) e->session.reset();  // no worker runs any more
}

std::size_t Api::kernel_count() const {
  std::size_t n = 0;
  for (const auto& [group, pool] : pools_) n += pool.kernels.size();
  return n;
}

KernelPool& Api::pool_for(const std::string& group) {
  auto it = pools_.find(group);
  return it == pools_.end() ? pools_.begin()->second : it->second;
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
  KernelPool& pool = pool_for(entry ? entry->group : r.param("group"));
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
  if (!pool_for(std::string()).scheduler->submit(key, std::move(work), 0))
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
  if (recorder_ && !enroll(r, who, *entry, resumed, reply)) return nullptr;
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
  Kernel& at = in_pool(group, k) ? k : *pool_for(group).kernels.front();
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
    if (resumed) resume_world(*entry);
  }
  return entry;
}

bool Api::enroll(const HttpRequest& r, std::optional<Login>& login, SessionEntry& entry,
                 bool& resumed, HttpReply& reply) {
  // docs/studio.md §7 "Participants and resume": a login that is a participant resumes; a new
  // one, or a guest (enrolled as account P<n> with a login cookie), joins while the study is open.
  if (login) {
    if (auto p = recorder_->participant_of(login->name)) {
      entry.participant = p->participant;
      entry.group = p->group;
      resumed = true;
      return true;
    }
  }
  if (!recorder_->open()) {
    reply = error_reply(403, "study_closed", "this study takes no new participants");
    return false;
  }
  if (!login) {
    const std::string id =
        recorder_->next_id([this](const std::string& name) { return accounts_.name_taken(name); });
    const auto valid_for = std::chrono::hours(24) * options_.login_days;
    const std::string code = accounts_.invite(
        id, Role::participant, std::chrono::duration_cast<std::chrono::seconds>(valid_for));
    login = accounts_.redeem(code, valid_for);
    if (!login) {
      reply = error_reply(500, "internal", "could not enroll participant " + id);
      return false;
    }
    reply.set_header("Set-Cookie", login_cookie_header(login->token, valid_for));
  }
  const ParticipantState p = recorder_->enroll(login->name, r.param("group"));
  entry.participant = p.participant;
  entry.group = p.group;
  return true;
}

void Api::resume_world(SessionEntry& entry) {
  const Json world = recorder_->resume_world(entry.participant);
  if (!world.is_object()) return;
  const std::string request =
      Json{{"op", "world"}, {"world", world}, {"studio", {{"why", "resume"}}}}.dump();
  entry.session->activate();
  if (auto* ops = entry.session->extension<StudioOps>()) ops->reset();
  const auto start = Clock::now();
  const std::string answer = entry.session->handle_line(request);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  recorder_->record(entry, request, answer, ms, "server");
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

bool Api::in_pool(const std::string& group, const Kernel& k) {
  const auto& kernels = pool_for(group).kernels;
  return std::any_of(kernels.begin(), kernels.end(),
                     [&](const std::unique_ptr<Kernel>& p) { return p.get() == &k; });
}

HttpReply Api::run(SessionEntry& entry, Kernel& free, const HttpRequest& r) {
  // A study's new session may run on a kernel of the pool the request named, not of the group
  // it was assigned: it stays on its own kernel then.
  Kernel& k = in_pool(entry.group, free) ? free : *entry.kernel;
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
  Kernel& k = *pool_for(entry ? entry->group : std::string()).kernels.front();
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
