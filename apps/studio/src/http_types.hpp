#pragma once
// The HTTP request and reply as the studio's routes see them, independent of the HTTP library
// (http_transport.cpp fills and sends them). docs/studio.md §2 (transport).
#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace flipper::studio {

struct HttpRequest {
  std::string method;                        ///< "GET", "POST", ...
  std::string path;                          ///< the target without the query ("/api/v1/request")
  std::map<std::string, std::string> query;  ///< decoded query parameters (first value wins)
  std::string raw_query;                     ///< the query as sent (after '?'), not decoded
  std::string host;                          ///< the Host header
  std::string origin;                        ///< the Origin header
  std::string sec_fetch_site;                ///< the Sec-Fetch-Site header
  std::string cookie;                        ///< the Cookie header
  std::string body;
  /// The client's address (no port): the socket's peer, or the client a trusted proxy names
  /// in X-Forwarded-For (docs/serve.md "Behind a proxy"). Per-address limits count on it.
  std::string peer;
  /// Whether the client's page is HTTPS: a TLS connection, or a trusted proxy's
  /// X-Forwarded-Proto: https. Its cookies are then Secure and its Origin https://.
  bool secure = false;

  /// A query parameter, or "" when absent.
  std::string param(const std::string& name) const {
    auto it = query.find(name);
    return it == query.end() ? std::string() : it->second;
  }
};

struct HttpReply {
  int status = 200;
  std::string body;
  std::string content_type = "application/json";
  std::vector<std::pair<std::string, std::string>> headers;
  void set_header(std::string name, std::string value) {
    for (auto& [k, v] : headers)
      if (k == name) {
        v = std::move(value);
        return;
      }
    headers.emplace_back(std::move(name), std::move(value));
  }
};

/// A route's answer arrives through this callback, from any thread, exactly once.
using Respond = std::function<void(HttpReply)>;
/// A route: answers `request` now or later (a worker thread) through `respond`.
using Route = std::function<void(const HttpRequest& request, Respond respond)>;

/// The headers every answer carries unless its route set them (docs/studio.md §2 "Headers"):
/// nosniff, X-Frame-Options DENY, Referrer-Policy no-referrer, and a Content-Security-Policy
/// that loads nothing and forbids framing.
const std::vector<std::pair<std::string, std::string>>& security_headers();
/// {"ok":false,"op":null,"error":{"code","message"}}: the protocol's error object for refusals
/// made before a request reaches a session.
std::string error_body(const std::string& code, const std::string& message);
/// A reply with that body.
HttpReply error_reply(int status, const std::string& code, const std::string& message);
/// `message` with every absolute path cut to its last part ('/srv/study/queries.jsonl' ->
/// 'queries.jsonl'): what a client may see of the server's files (docs/studio.md §2 "Messages").
/// error_body applies it to every message.
std::string without_paths(const std::string& message);
/// `job()`, or the reply for what it threw (logged on stderr in full): write_failed and
/// read_only 503, any other sdk::Error 500 with its code, anything else 500 internal. A job
/// never ends the server.
HttpReply answer_or_failure(const std::function<HttpReply()>& job);
/// A JSON answer, never cached.
HttpReply json_reply(int status, const nlohmann::json& body);

}  // namespace flipper::studio
