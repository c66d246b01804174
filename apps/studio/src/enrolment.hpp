#pragma once
// Study mode's side of opening a session (docs/studio.md §7 "Participants and resume"): who the
// participant is, and the world a resumed participant had.
#include <optional>

#include "flipper/studio/accounts.hpp"
#include "flipper/studio/server.hpp"
#include "http_types.hpp"
#include "registry.hpp"

namespace flipper::studio {

class Recorder;

/// Who a new session's participant is: a login that is a participant resumes (`resumed`), a new
/// login joins while the study is open, a guest is enrolled as account P<n> with a login cookie in
/// `reply`. Sets the entry's participant and group; false with `reply` set when refused.
bool enroll(Recorder& recorder, AccountStore& accounts, const ServeOptions& options,
            const HttpRequest& r, std::optional<Login>& login, SessionEntry& entry, bool& resumed,
            HttpReply& reply);

/// A resumed participant's session gets the world it had: a request the server makes, recorded
/// as the server's. Call under the session's kernel lock.
void resume_world(Recorder& recorder, SessionEntry& entry);

}  // namespace flipper::studio
