#include "study_http.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cookies.hpp"
#include "flipper/sdk/errors.hpp"
#include "recorder.hpp"
#include "study.hpp"

namespace flipper::studio {
using kernel::Json;

namespace {

constexpr std::size_t kMaxEventBytes = 4096;

// The participant a researcher's request body names: {"participant": NAME}.
std::optional<std::string> participant_named(const HttpRequest& r) {
  const Json body = Json::parse(r.body, nullptr, false);
  if (!body.is_object() || !body.contains("participant") || !body["participant"].is_string())
    return std::nullopt;
  return body["participant"].get<std::string>();
}

HttpReply no_study() {
  return error_reply(404, "no_study", "this server runs no study (serve.study)");
}

}  // namespace

void StudyEndpoints::later(const std::string& key, std::function<HttpReply()> job,
                           const Respond& respond) {
  auto work = [job = std::move(job), respond](int) { respond(answer_or_failure(job)); };
  if (!scheduler_.submit(key, std::move(work)))
    respond(error_reply(429, "session_busy", "too many requests waiting"));
}

StudyEndpoints::Researcher StudyEndpoints::researcher(const HttpRequest& r) const {
  if (!sessions_.recorder()) return {no_study(), {}};
  const std::optional<Login> login = accounts_.resume(login_cookie(r.cookie));
  if (!login)
    return {error_reply(401, "login_required", "log in as the study's researcher (an admin)"), {}};
  if (login->role != Role::admin)
    return {error_reply(403, "forbidden", "only an administrator sees the study's recording"), {}};
  return {std::nullopt, login->name};
}

StudyEndpoints::Researcher StudyEndpoints::researcher_change(const HttpRequest& r) const {
  Researcher who = researcher(r);
  if (!who.refusal && !hosts_.allows_origin(r))
    who.refusal = error_reply(403, "cross_origin", "must come from this server's page");
  return who;
}

void StudyEndpoints::event(const HttpRequest& r, const Respond& respond) {
  if (!sessions_.recorder()) return respond(no_study());
  if (!hosts_.allows_origin(r))
    return respond(error_reply(403, "cross_origin", "events must come from this server's page"));
  const std::string token = r.param("session");
  auto job = [this, r, token]() -> HttpReply {
    if (r.body.size() > kMaxEventBytes)
      return error_reply(400, "bad_request", "an event is at most 4096 bytes");
    const Json body = Json::parse(r.body, nullptr, false);
    const std::string kind = body.is_object() && body.contains("kind") && body["kind"].is_string()
                                 ? body["kind"].get<std::string>()
                                 : std::string();
    const bool shaped =
        (kind == "flip" && body.contains("rank") && body["rank"].is_number_integer() &&
         (!body.contains("formula") || body["formula"].is_string())) ||
        kind == "reject" ||
        (kind == "page_load" && (!body.contains("reloaded") || body["reloaded"].is_boolean()));
    if (!shaped)
      return error_reply(400, "bad_request",
                         "send {\"kind\":\"flip\",\"rank\":N,\"formula\":F}, {\"kind\":\"reject\"} "
                         "or {\"kind\":\"page_load\",\"reloaded\":B}");
    std::shared_ptr<SessionEntry> entry = sessions_.registry().find(token);
    if (!entry) return error_reply(404, "unknown_session", "no session has this token");
    const std::optional<Login> login = accounts_.resume(login_cookie(r.cookie));
    if (!entry->account.empty() && (!login || login->name != entry->account))
      return error_reply(401, "login_required",
                         "this session belongs to account '" + entry->account + "'");
    if (!sessions_.registry().admit(*entry, Clock::now()))
      return error_reply(429, "rate_limited", "too many requests in this session");
    sessions_.recorder()->event(*entry, body);
    return json_reply(200, Json{{"ok", true}});
  };
  later(token.empty() ? "event:" + r.peer : token, std::move(job), respond);
}

void StudyEndpoints::overview(const HttpRequest& r, const Respond& respond) {
  auto who = researcher(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  later(
      "study:" + r.peer, [this] { return json_reply(200, sessions_.recorder()->overview()); },
      respond);
}

void StudyEndpoints::recording(const HttpRequest& r, const Respond& respond) {
  auto who = researcher(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const std::string prefix = "/api/v1/study/recording/";
  const std::string name = r.path.substr(std::min(r.path.size(), prefix.size()));
  const auto& files = Recorder::files();
  if (std::find(files.begin(), files.end(), name) == files.end())
    return respond(
        error_reply(404, "not_found", "the recording has no file '" + name.substr(0, 100) + "'"));
  auto job = [this, name, account = who.account, peer = r.peer]() -> HttpReply {
    std::ifstream in(std::filesystem::path(sessions_.study()->record_dir()) / name,
                     std::ios::binary);
    if (!in) return error_reply(404, "not_found", "'" + name + "' is not written yet");
    std::ostringstream text;
    text << in.rdbuf();
    sessions_.recorder()->audit(account, peer, "download", Json{{"file", name}});
    HttpReply reply;
    reply.body = text.str();
    reply.content_type = name.ends_with(".jsonl") ? "application/x-ndjson" : "application/json";
    reply.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
    reply.set_header("Cache-Control", "no-store");
    return reply;
  };
  later("study:" + r.peer, std::move(job), respond);
}

void StudyEndpoints::close(const HttpRequest& r, const Respond& respond) {
  auto who = researcher_change(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const Json body = Json::parse(r.body, nullptr, false);
  if (!body.is_object() || !body.contains("open") || !body["open"].is_boolean())
    return respond(error_reply(400, "bad_request", "send {\"open\": false} or {\"open\": true}"));
  const bool open = body["open"].get<bool>();
  auto job = [this, open, account = who.account, peer = r.peer] {
    sessions_.recorder()->set_open(open);
    sessions_.recorder()->audit(account, peer, open ? "reopen" : "close", Json::object());
    return json_reply(200, sessions_.recorder()->overview());
  };
  later("study:" + r.peer, std::move(job), respond);
}

void StudyEndpoints::invite(const HttpRequest& r, const Respond& respond) {
  auto who = researcher_change(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const std::optional<std::string> named = participant_named(r);
  if (!named) return respond(error_reply(400, "bad_request", "send {\"participant\": NAME}"));
  const std::string& name = *named;
  auto job = [this, name, account = who.account, peer = r.peer]() -> HttpReply {
    // Only a participant's account, or a new one: never a code for another account (an admin's).
    const bool account_known = accounts_.find(name).has_value();
    if (account_known && !sessions_.recorder()->participant_of(name))
      return error_reply(409, "not_a_participant",
                         "'" + name + "' is an account that is not a participant of this study");
    try {
      const std::string code =
          accounts_.invite(name, Role::participant, std::chrono::hours(24) * 7);
      sessions_.recorder()->audit(account, peer, "invite",
                                  Json{{"participant", name}, {"known", account_known}});
      return json_reply(200, Json{{"ok", true},
                                  {"participant", name},
                                  {"code", code},
                                  {"url", "/?code=" + code},
                                  {"known", account_known}});
    } catch (const sdk::Error& e) {
      return error_reply(400, e.code(), e.what());
    }
  };
  later("study:" + r.peer, std::move(job), respond);
}

void StudyEndpoints::end(const HttpRequest& r, const Respond& respond) {
  auto who = researcher_change(r);
  if (who.refusal) return respond(std::move(*who.refusal));
  const std::optional<std::string> named = participant_named(r);
  if (!named) return respond(error_reply(400, "bad_request", "send {\"participant\": NAME}"));
  const std::string& name = *named;
  auto job = [this, name, account = who.account, peer = r.peer]() -> HttpReply {
    if (!sessions_.recorder()->participant_of(name))
      return error_reply(404, "not_a_participant",
                         "'" + name.substr(0, 100) + "' is not a participant of this study");
    const int logins = accounts_.revoke(name);
    sessions_.recorder()->audit(account, peer, "end",
                                Json{{"participant", name}, {"logins", logins}});
    return json_reply(200, Json{{"ok", true}, {"participant", name}, {"logins", logins}});
  };
  later("study:" + r.peer, std::move(job), respond);
}

void StudyEndpoints::next(const HttpRequest& r, const Respond& respond) {
  if (!sessions_.recorder()) return respond(no_study());
  if (!hosts_.allows_origin(r))
    return respond(error_reply(403, "cross_origin", "must come from this server's page"));
  auto job = [this, r]() -> HttpReply {
    const std::string token = login_cookie(r.cookie);
    const std::optional<Login> login = accounts_.resume(token);
    if (!login || !sessions_.recorder()->participant_of(login->name))
      return error_reply(401, "login_required", "only a participant's own page ends its login");
    accounts_.logout(token);
    HttpReply reply = json_reply(200, Json{{"ok", true}, {"participant", login->name}});
    reply.set_header("Set-Cookie", login_cookie_cleared());
    return reply;
  };
  later("next:" + r.peer, std::move(job), respond);
}

}  // namespace flipper::studio
