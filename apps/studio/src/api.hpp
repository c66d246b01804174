#pragma once
// The HTTP mapping of the session protocol (docs/serve.md, docs/studio.md): POST /api/v1/request
// and GET /api/v1/info, independent of the HTTP library: the routes take an HttpRequest and answer
// through a callback. The sessions they run on are sessions.hpp's (kernel pools, opening and
// enrolment, eviction); logins are auth_http.hpp, the study's endpoints study_http.hpp.
// Protocol requests run on a kernel pool's workers, one at a time per session; each kernel is
// used by one request at a time (its parser, scorer, planner caches and naturalizer are not
// thread-safe), and a session moves to whichever kernel of its pool is free (docs/studio.md §5).
#include <atomic>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipper/studio/accounts.hpp"
#include "flipper/studio/server.hpp"
#include "host_policy.hpp"
#include "http_types.hpp"
#include "scheduler.hpp"
#include "sessions.hpp"

namespace flipper::studio {

class Api {
 public:
  /// `scheduler` runs the work that needs no kernel (info); each kernel has its own.
  Api(Sessions& sessions, ServeOptions options, AccountStore& accounts, Scheduler& scheduler,
      const HostPolicy& hosts);

  /// POST /api/v1/request[?session=TOKEN]
  void request(const HttpRequest& request, const Respond& respond);
  /// GET /api/v1/info[?session=TOKEN]: what the page needs besides the protocol.
  void info(const HttpRequest& request, const Respond& respond);

 private:
  /// The job of one protocol request, on the worker of kernel `k`.
  HttpReply serve(const HttpRequest& request, Kernel& k);
  HttpReply run(SessionEntry& entry, Kernel& free, const HttpRequest& request);
  HttpReply info_reply(const HttpRequest& request);

  Sessions& sessions_;
  ServeOptions options_;
  AccountStore& accounts_;
  Scheduler& scheduler_;
  const HostPolicy& hosts_;
  std::atomic<std::uint64_t> new_requests_{0};
};

}  // namespace flipper::studio
