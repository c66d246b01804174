#include "api.hpp"

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "recorder.hpp"
#include "study.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;

namespace {

// Errors about the request's shape (the body is not a protocol request): HTTP 400. Every other
// answer, ok or not, is the session's answer: HTTP 200.
bool is_request_error(const std::string& code) {
  return code == "bad_json" || code == "unknown_op" || code == "missing_field" ||
         code == "bad_request";
}

int status_of(const std::string& answer) {
  if (answer.rfind("{\"ok\":false", 0) != 0) return 200;
  const Json a = Json::parse(answer, nullptr, false);
  if (a.is_discarded()) return 200;
  return is_request_error(a["error"].value("code", std::string())) ? 400 : 200;
}

bool inside(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p)
    if (p == path.end() || *p != *r) return false;
  return true;
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

Json world_files(const std::string& root) {
  Json out = Json::array();
  std::error_code ec;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(root, ec))
    if (e.is_regular_file() && e.path().extension() == ".json")
      names.insert(e.path().filename().string());
  for (const auto& n : names) out.push_back(n);
  return out;
}

}  // namespace

std::string error_body(const std::string& code, const std::string& message, const Json* request) {
  Json a;
  a["ok"] = false;
  a["op"] = nullptr;
  if (request != nullptr && request->is_object()) {
    if (auto it = request->find("op"); it != request->end()) a["op"] = *it;
    if (auto it = request->find("id"); it != request->end()) a["id"] = *it;
  }
  a["error"] = Json{{"code", code}, {"message", message}};
  return a.dump(-1, ' ', false, Json::error_handler_t::replace);
}

bool same_origin(const HttpRequest& r) {
  // Fetch metadata first: a browser marks cross-site requests itself.
  if (!r.sec_fetch_site.empty() && r.sec_fetch_site != "same-origin" && r.sec_fetch_site != "none")
    return false;
  if (r.origin.empty()) return true;  // not a browser (curl, programs, the benchmark)
  return r.origin == "http://" + r.host;
}

Api::Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options)
    : options_(std::move(options)),
      registry_(RegistryLimits{options_.max_sessions, std::chrono::seconds(options_.session_idle_s),
                               options_.rate_per_second, options_.rate_burst}) {
  for (const auto& [group, config] : kernels) {
    Kernel k;
    k.runtime = kernel::make_runtime(config);
    k.factory = std::make_unique<kernel::SessionHost>(kernel::open_host(k.runtime));
    std::error_code ec;
    k.world_root =
        fs::weakly_canonical(fs::path(config.get_path("world.file")).parent_path(), ec).string();
    kernels_.emplace(group, std::move(k));
  }
}

Api::~Api() = default;

Kernel& Api::kernel_for(const std::string& group) {
  auto it = kernels_.find(group);
  return it == kernels_.end() ? kernels_.begin()->second : it->second;
}

// The request's session: found by token, or created when the request names none. Sets the
// reply's error (and returns null) for unknown tokens and a full server.
SessionEntry* Api::session_for(const HttpRequest& r, HttpReply& reply) {
  const auto now = Clock::now();
  if (!r.session.empty()) {
    SessionEntry* e = registry_.find(r.session);
    if (e == nullptr) {
      reply.status = 404;
      reply.body = error_body("unknown_session",
                              "no session has this token (it expired or the server restarted); "
                              "send the request without 'session' to start a new one");
    }
    return e;
  }
  std::string group = r.group;
  if (study_) group = study_->assign_group(group);
  Kernel& k = kernel_for(group);
  SessionEntry* e = registry_.add(k.factory->open(), now);
  if (e == nullptr) {
    reply.status = 503;
    reply.body =
        error_body("too_many_sessions", "the server has " + std::to_string(options_.max_sessions) +
                                            " sessions (serve.max_sessions); try later");
    return nullptr;
  }
  e->group = group;
  if (study_) {
    e->participant = study_->next_participant();
    if (recorder_) recorder_->session_started(*e);
  }
  return e;
}

HttpReply Api::request(const HttpRequest& r) {
  HttpReply reply;
  reply.headers.emplace_back("Cache-Control", "no-store");
  if (!same_origin(r)) {
    reply.status = 403;
    reply.body = error_body("cross_origin",
                            "state-changing requests must come from this "
                            "server's own page (Origin '" +
                                r.origin + "')");
    return reply;
  }
  const Json parsed = Json::parse(r.body, nullptr, false);
  std::lock_guard lock(mutex_);
  SessionEntry* entry = session_for(r, reply);
  if (entry == nullptr) return reply;
  reply.headers.emplace_back("Flipper-Session", entry->token);
  reply.headers.emplace_back("Flipper-User", entry->session->user());
  if (!registry_.admit(*entry, Clock::now())) {
    reply.status = 429;
    reply.body = error_body("rate_limited",
                            "too many requests in this session (serve.rate_per_second)", &parsed);
    return reply;
  }
  kernel::Session& session = *entry->session;
  Kernel& k = kernel_for(entry->group);
  std::string body = r.body;
  if (parsed.is_object()) {
    const std::string op =
        parsed.value("op", Json()).is_string() ? parsed["op"].get<std::string>() : std::string();
    // A session acts as one of its own users only.
    if (op == "user" && parsed.contains("name") && parsed["name"].is_string() &&
        !parsed["name"].get<std::string>().empty() &&
        !registry_.claim_user(parsed["name"].get<std::string>(), entry->token)) {
      reply.body = error_body(
          "forbidden",
          "user '" + parsed["name"].get<std::string>() + "' belongs to another session", &parsed);
      return reply;
    }
    // World files: only the config's world directory, resolved there (never the server's cwd).
    if (op == "world" && parsed.contains("file") && parsed["file"].is_string() &&
        (!parsed.contains("world") || parsed["world"].is_null())) {
      std::error_code ec;
      const fs::path file =
          fs::weakly_canonical(fs::path(k.world_root) / parsed["file"].get<std::string>(), ec);
      if (ec || !inside(file, fs::path(k.world_root))) {
        reply.body = error_body("forbidden",
                                "over HTTP a world file must lie in " + k.world_root +
                                    " (or send the world object in 'world')",
                                &parsed);
        return reply;
      }
      Json rewritten = parsed;
      rewritten["file"] = file.string();
      body = rewritten.dump();
    }
  }
  k.factory->activate(session);
  const auto start = Clock::now();
  std::string answer = session.handle_line(body);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (answer.empty()) {
    reply.status = 400;
    reply.body = error_body("bad_json", "the body is empty: send one request object");
    return reply;
  }
  reply.status = status_of(answer);
  reply.headers.back().second = session.user();  // after a `user` op: the new name
  if (recorder_ && parsed.is_object()) recorder_->record(*entry, parsed, answer, ms);
  reply.body = std::move(answer);
  return reply;
}

HttpReply Api::info(const HttpRequest& r) {
  HttpReply reply;
  reply.headers.emplace_back("Cache-Control", "no-store");
  std::lock_guard lock(mutex_);
  SessionEntry* entry = r.session.empty() ? nullptr : registry_.find(r.session);
  Kernel& k = kernel_for(entry ? entry->group : std::string());
  const kernel::Config& c = k.runtime->config;
  Json out{{"ok", true},
           {"sharing", c.get_string("lexicon.sharing")},
           {"k", c.get_int("session.k")},
           {"max_chars", c.get_int("input.max_chars")},
           {"vocabulary", vocabulary(*k.runtime)},
           {"worlds", world_files(k.world_root)},
           {"study", nullptr}};
  if (study_) out["study"] = study_->page_json(entry);
  reply.body = out.dump();
  return reply;
}

}  // namespace flipper::studio
