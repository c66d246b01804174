#pragma once
// Study mode's own HTTP endpoints (docs/studio.md §7): the page's events and the researcher's
// view. The protocol exchanges themselves go through Api (api.hpp) and are recorded there.
//   POST /api/v1/study/event?session=T   {"kind":"flip","rank","formula"} | {"kind":"reject"} |
//                                        {"kind":"page_load","reloaded"}: a queries.jsonl line
//   GET  /api/v1/study/overview          (admin) participants, their group, task, counts, files
//   GET  /api/v1/study/recording/NAME    (admin) one file of the recording, as an attachment
//   POST /api/v1/study/close {"open":b}  (admin) stop (or resume) taking new participants
//   POST /api/v1/study/invite {"participant":P}  (admin) a one-time login code for P: a known
//                                        participant resumes on another device, a new name joins
//   POST /api/v1/study/end {"participant":P}     (admin) ends every login of P: the computer P
//                                        used takes the next participant at its next request
//   POST /api/v1/study/next              (the participant's page, kiosk mode) ends this login:
//                                        the page reloads as the next participant
//   GET  /api/v1/study/lexicon?group=G  (admin) group G's lexicon: its history (newest first, at
//                                        most 200 entries) and the definitions held for approval
//   POST /api/v1/study/lexicon/approve {"group":G,"id":"hN"}  (admin) stores a held definition
//   POST /api/v1/study/lexicon/reject {"group":G,"id":"hN","reason":R}  (admin) drops it
//                                        (lexicon.moderation: hold_new; docs/naturalization.md §5)
// The researcher's endpoints answer 401 login_required without a login, 403 forbidden for a
// login that is not an administrator; a server without a study answers 404 no_study. Each close,
// reopen, invitation, end, approval, rejection and download is a line of the recording's
// audit.jsonl (§7 "Audit").
#include "flipper/studio/accounts.hpp"
#include "host_policy.hpp"
#include "http_types.hpp"
#include "scheduler.hpp"
#include "sessions.hpp"

namespace flipper::studio {

class StudyEndpoints {
 public:
  StudyEndpoints(Sessions& sessions, AccountStore& accounts, Scheduler& scheduler,
                 const HostPolicy& hosts)
      : sessions_(sessions), accounts_(accounts), scheduler_(scheduler), hosts_(hosts) {}

  void event(const HttpRequest& request, const Respond& respond);
  void overview(const HttpRequest& request, const Respond& respond);
  void recording(const HttpRequest& request, const Respond& respond);
  void close(const HttpRequest& request, const Respond& respond);
  void invite(const HttpRequest& request, const Respond& respond);
  void end(const HttpRequest& request, const Respond& respond);
  void next(const HttpRequest& request, const Respond& respond);
  /// The lexicon page: history and moderation queue (lexicon_http.cpp).
  void lexicon(const HttpRequest& request, const Respond& respond);
  void moderate(const HttpRequest& request, const Respond& respond, bool approve);

 private:
  /// The researcher's account name, or the refusal.
  struct Researcher {
    std::optional<HttpReply> refusal;
    std::string account;
  };
  Researcher researcher(const HttpRequest& request) const;
  /// researcher(), and a change of the study comes from this server's own page (else 403).
  Researcher researcher_change(const HttpRequest& request) const;
  void later(const std::string& key, std::function<HttpReply()> job, const Respond& respond);

  Sessions& sessions_;
  AccountStore& accounts_;
  Scheduler& scheduler_;
  const HostPolicy& hosts_;
};

}  // namespace flipper::studio
