#pragma once
// GET /sempre: the 2018 server's HTTP API (docs/sempre.md), so the original study's web client
// and other SEMPRE clients run on Flipper unchanged. Independent of the HTTP library, like
// api.hpp: the method and the raw query string in, status, headers and body out. Each sessionId
// is a kernel session over the plain server's kernel (same runtime, lexicon and sharing mode as
// /api/v1) whose user, the author of the rules defined there, is sempre_user(sessionId). Its
// sessions are entries of the server's one session table: they count in serve.max_sessions, the
// per-address limits and the memory budget like /api/v1's guests (docs/sempre.md "Bounds").
// Browsers are answered only from the page's own origin and serve.sempre_origins.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sempre_session.hpp"
#include "sessions.hpp"

namespace flipper::studio {

struct SempreRequest {
  std::string method;  ///< "GET", "OPTIONS", ...
  std::string query;   ///< the raw query string (after '?'), percent-encoded
  std::string peer;    ///< the client's address
  std::string origin;  ///< the Origin header ("" when none)
  /// HostPolicy::allows_origin: the server's own page, or no browser (no Origin, not marked
  /// cross-site by Sec-Fetch-Site).
  bool own_origin = true;
};

class SempreEndpoint {
 public:
  SempreEndpoint(Sessions& sessions, const ServeOptions& options);
  HttpReply handle(const SempreRequest& request);

 private:
  struct Slot {
    std::shared_ptr<SessionEntry> entry;  ///< in the sessions' registry while the session lives
    SempreSession state;
  };
  /// The sessionId's session, opened on first use (admitted by the registry as a new guest
  /// session from `peer`); null with `refusal` set when the registry refuses it. Call under the
  /// kernel lock.
  Slot* slot_for(Kernel& kernel, const std::string& id, const std::string& peer,
                 std::optional<SessionRegistry::Refusal>& refusal);
  /// The Access-Control-Allow-Origin of an answer to `request` ("" none: the server's own page
  /// or no browser), or nullopt when the origin may not use /sempre.
  std::optional<std::string> allowed_origin(const SempreRequest& request) const;

  Sessions& sessions_;
  std::vector<std::string> origins_;     ///< serve.sempre_origins
  std::map<std::string, Slot> slots_;    ///< by sessionId; under the kernel lock
  std::atomic<std::uint64_t> count_{0};  ///< requests answered (stats.count)
};

/// An answer's body: {"candidates": [...], ["error": {"code", "message"},] "lines": [...],
/// "stats": {..., "type", "count", "walltime"}} (docs/sempre.md), compact, invalid UTF-8 replaced.
/// `error_code` "" gives no "error" member.
std::string sempre_body(const std::string& type, std::uint64_t count, double seconds,
                        const SempreAnswer& answer, const std::string& error_code = {});

/// The query string's parameters, percent-decoded ('+' is a space, as in the original's
/// form decoding). Throws sdk::Error(bad_request) for a malformed escape.
std::map<std::string, std::string> decode_query_string(std::string_view query);

}  // namespace flipper::studio
