#include "sessions.hpp"

#include <chrono>

#include "enrolment.hpp"
#include "recorder.hpp"
#include "studio_ops.hpp"

namespace flipper::studio {

namespace {

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

Sessions::Sessions(const std::vector<std::pair<std::string, kernel::Config>>& kernels,
                   ServeOptions options, AccountStore& accounts)
    : options_(std::move(options)),
      accounts_(accounts),
      pools_(kernels, options_),
      registry_(registry_limits(options_)) {
  registry_.set_memory_budget(pools_.session_budget(options_));
}

Sessions::~Sessions() {
  pools_.stop_workers();  // their workers use the sessions
  bury_evicted();
  for (auto& e : graves_) e->session.reset();  // no worker runs any more
}

void Sessions::bury_evicted() {
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

void Sessions::run_on_plain_kernel(const std::string& key, std::function<HttpReply()> job,
                                   const Respond& respond) {
  // Pinned to the first kernel: /sempre keeps its sessions there (docs/sempre.md).
  auto work = [job = std::move(job), respond](int) { respond(answer_or_failure(job)); };
  if (!pools_.pool_for(std::string()).scheduler->submit(key, std::move(work), 0))
    respond(error_reply(429, "session_busy",
                        "this session already has requests waiting; send the next one after "
                        "the answer"));
}

std::shared_ptr<SessionEntry> Sessions::open(const HttpRequest& r,
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

void Sessions::install_studio_ops(SessionEntry& entry, Kernel& k) {
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

void Sessions::move_to(SessionEntry& entry, Kernel& k) {
  entry.session->rebind(k.runtime, k.host->extensions);  // the studio's ops come along
  entry.kernel = &k;
}

}  // namespace flipper::studio
