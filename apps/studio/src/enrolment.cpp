#include "enrolment.hpp"

#include <chrono>
#include <nlohmann/json.hpp>

#include "cookies.hpp"
#include "recorder.hpp"
#include "studio_ops.hpp"

namespace flipper::studio {
using kernel::Json;

bool enroll(Recorder& recorder, AccountStore& accounts, const ServeOptions& options,
            const HttpRequest& r, std::optional<Login>& login, SessionEntry& entry, bool& resumed,
            HttpReply& reply) {
  // docs/studio.md §7 "Participants and resume": a login that is a participant resumes; a new
  // one, or a guest (enrolled as account P<n> with a login cookie), joins while the study is open.
  if (login) {
    if (auto p = recorder.participant_of(login->name)) {
      entry.participant = p->participant;
      entry.group = p->group;
      resumed = true;
      return true;
    }
  }
  if (!recorder.open()) {
    reply = error_reply(403, "study_closed", "this study takes no new participants");
    return false;
  }
  if (!login) {
    const std::string id = recorder.next_id(
        [&accounts](const std::string& name) { return accounts.name_taken(name); });
    const auto valid_for = std::chrono::hours(24) * options.login_days;
    const std::string code = accounts.invite(
        id, Role::participant, std::chrono::duration_cast<std::chrono::seconds>(valid_for));
    login = accounts.redeem(code, valid_for);
    if (!login) {
      reply = error_reply(500, "internal", "could not enroll participant " + id);
      return false;
    }
    reply.set_header("Set-Cookie", login_cookie_header(login->token, valid_for));
  }
  const ParticipantState p = recorder.enroll(login->name, r.param("group"));
  entry.participant = p.participant;
  entry.group = p.group;
  return true;
}

void resume_world(Recorder& recorder, SessionEntry& entry) {
  const Json world = recorder.resume_world(entry.participant);
  if (!world.is_object()) return;
  const std::string request =
      Json{{"op", "world"}, {"world", world}, {"studio", {{"why", "resume"}}}}.dump();
  entry.session->activate();
  if (auto* ops = entry.session->extension<StudioOps>()) ops->reset();
  const auto start = Clock::now();
  const std::string answer = entry.session->handle_line(request);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  recorder.record(entry, request, answer, ms, "server");
}

}  // namespace flipper::studio
