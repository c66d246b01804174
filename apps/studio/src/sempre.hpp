#pragma once
// GET /sempre: the 2018 server's HTTP API (docs/sempre.md), so the original study's web client
// and other SEMPRE clients run on Flipper unchanged. Independent of the HTTP library, like
// api.hpp: the method and the raw query string in, status, headers and body out. Each sessionId
// is a kernel session over the plain server's kernel (same runtime, lexicon and sharing mode as
// /api/v1) whose user, the author of the rules defined there, is sempre_user(sessionId). Every
// answer allows any origin (Access-Control-Allow-Origin: *), which is why serve.sempre is off
// by default.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>

#include "api.hpp"
#include "sempre_session.hpp"

namespace flipper::studio {

struct SempreRequest {
  std::string method;  ///< "GET", "OPTIONS", ...
  std::string query;   ///< the raw query string (after '?'), percent-encoded
};

class SempreEndpoint {
 public:
  /// Sessions are limited like /api/v1's (serve.max_sessions, serve.session_idle_s).
  SempreEndpoint(Api& api, const ServeOptions& options);
  HttpReply handle(const SempreRequest& request);

 private:
  /// The sessionId's session, opened on first use. Null when the table is full of sessions used
  /// within serve.session_idle_s. Call under the kernel lock.
  SempreSession* session_for(Kernel& kernel, const std::string& id);

  Api& api_;
  std::size_t max_sessions_;
  std::chrono::seconds idle_;
  std::map<std::string, SempreSession> sessions_;  ///< by sessionId; under the kernel lock
  std::atomic<std::uint64_t> count_{0};            ///< requests answered (stats.count)
};

/// The query string's parameters, percent-decoded ('+' is a space, as in the original's
/// form decoding). Throws sdk::Error(bad_request) for a malformed escape.
std::map<std::string, std::string> decode_query_string(std::string_view query);

}  // namespace flipper::studio
