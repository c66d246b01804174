#pragma once
// The HTTP mapping of the session protocol, independent of the HTTP library: one request object
// in, exactly the answer `flipper session` gives out, plus the transport's own checks (same
// origin, unguessable session tokens, user claims, rate limit). One mutex serialises the kernel:
// sessions share the parser, scorer and lexicon, which are not thread-safe.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "flipper/wiring/session_factory.hpp"
#include "flipper/studio/server.hpp"
#include "registry.hpp"

namespace flipper::studio {

struct HttpRequest {
  std::string session;         ///< the `session` query parameter ("" when absent)
  std::string origin;          ///< the Origin header
  std::string host;            ///< the Host header
  std::string sec_fetch_site;  ///< the Sec-Fetch-Site header
  std::string body;
  std::string group;  ///< study mode: the group of a session created by this request
};

struct HttpReply {
  int status = 200;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

class Study;
class Recorder;

/// One kernel per lexicon mode: a plain server has one ("" group), a study one per group.
struct Kernel {
  std::shared_ptr<kernel::Runtime> runtime;
  std::unique_ptr<kernel::SessionHost> factory;
  std::string world_root;  ///< `world` requests may name files under this directory only
};

class Api {
 public:
  /// kernels: group name -> config (a plain server: {"", config}).
  Api(const std::vector<std::pair<std::string, kernel::Config>>& kernels, ServeOptions options);
  ~Api();

  /// POST /api/v1/request?session=TOKEN
  HttpReply request(const HttpRequest& request);
  /// GET /api/v1/info?session=TOKEN: what the page needs besides the protocol (vocabulary for
  /// "did you mean", sharing mode, world files, the study and the participant's place in it).
  HttpReply info(const HttpRequest& request);

  /// Runs `f(kernel)` with the plain server's kernel under the lock that serialises every kernel
  /// call: the /sempre endpoint (sempre.hpp) keeps its own sessions over that kernel.
  template <class F>
  decltype(auto) with_kernel(F&& f) {
    std::lock_guard lock(mutex_);
    return f(kernel_for(std::string()));
  }

  /// Study mode: every protocol exchange is handed to the recorder.
  void set_recorder(std::shared_ptr<Recorder> recorder) { recorder_ = std::move(recorder); }
  void set_study(std::shared_ptr<Study> study) { study_ = std::move(study); }

 private:
  Kernel& kernel_for(const std::string& group);
  SessionEntry* session_for(const HttpRequest& request, HttpReply& reply);

  ServeOptions options_;
  std::mutex mutex_;
  std::map<std::string, Kernel> kernels_;
  SessionRegistry registry_;
  std::shared_ptr<Recorder> recorder_;
  std::shared_ptr<Study> study_;
};

/// {"ok":false,"op":OP,"error":{"code","message"}} with the op and id of `request` when known.
std::string error_body(const std::string& code, const std::string& message,
                       const kernel::Json* request = nullptr);
/// Whether a state-changing request comes from the page's own origin (or from no browser).
bool same_origin(const HttpRequest& request);

}  // namespace flipper::studio
