// GET /sempre: transport, sessions and answers (see sempre.hpp; docs/sempre.md).
#include "sempre.hpp"

#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
namespace {

using Json = nlohmann::json;
constexpr std::size_t kMaxSessionIdBytes = 128;

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percent_decode(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%') {
      const int hi = i + 2 < s.size() ? hex_digit(s[i + 1]) : -1;
      const int lo = hi >= 0 ? hex_digit(s[i + 2]) : -1;
      if (lo < 0)
        throw sdk::Error(sdk::codes::kBadRequest,
                         "a '%' in the query string is not followed by two hex digits");
      out += static_cast<char>(hi * 16 + lo);
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// Printable ASCII without spaces: the client's base-36 ids, and UUIDs and the like.
bool valid_session_id(const std::string& id) {
  if (id.empty() || id.size() > kMaxSessionIdBytes) return false;
  for (const unsigned char c : id)
    if (c <= 0x20 || c >= 0x7F) return false;
  return true;
}

void cors(HttpReply& reply) {
  reply.headers.emplace_back("Access-Control-Allow-Origin", "*");
  reply.headers.emplace_back("Cache-Control", "no-store");
}

std::string body(const std::string& type, std::uint64_t count, double seconds,
                 const SempreAnswer& a, const std::string& error_code = {}) {
  Json stats = a.stats;
  stats["type"] = type;
  stats["count"] = count;
  stats["walltime"] = seconds;
  Json out{{"stats", std::move(stats)}, {"lines", a.lines}, {"candidates", a.candidates}};
  if (!error_code.empty())
    out["error"] = Json{{"code", error_code}, {"message", a.lines.empty() ? "" : a.lines[0]}};
  return out.dump(-1, ' ', false, Json::error_handler_t::replace);
}

HttpReply refused(int status, const std::string& code, const std::string& message,
                  std::uint64_t count) {
  HttpReply reply;
  cors(reply);
  reply.status = status;
  SempreAnswer a;
  a.lines.push_back(message);
  reply.body = body("error", count, 0.0, a, code);
  return reply;
}

}  // namespace

std::map<std::string, std::string> decode_query_string(std::string_view query) {
  std::map<std::string, std::string> out;
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    if (pair.empty()) continue;
    const std::size_t eq = pair.find('=');
    out.emplace(percent_decode(pair.substr(0, eq)),
                eq == std::string_view::npos ? std::string() : percent_decode(pair.substr(eq + 1)));
  }
  return out;
}

SempreEndpoint::SempreEndpoint(Api& api, const ServeOptions& options)
    : api_(api), max_sessions_(options.max_sessions), idle_(options.session_idle_s) {}

SempreSession* SempreEndpoint::session_for(Kernel& kernel, const std::string& id) {
  const auto now = std::chrono::steady_clock::now();
  auto it = sessions_.find(id);
  if (it == sessions_.end()) {
    if (sessions_.size() >= max_sessions_)
      std::erase_if(sessions_, [&](const auto& e) { return now - e.second.last_used >= idle_; });
    if (sessions_.size() >= max_sessions_) return nullptr;
    SempreSession s;
    s.session = kernel.host->open();
    s.session->set_user(sempre_user(id));
    it = sessions_.emplace(id, std::move(s)).first;
  }
  it->second.last_used = now;
  return &it->second;
}

HttpReply SempreEndpoint::handle(const SempreRequest& request) {
  const std::uint64_t count = ++count_;
  if (request.method == "OPTIONS") {  // a pre-flight: any origin may send the GET
    HttpReply reply;
    cors(reply);
    reply.status = 204;
    reply.headers.emplace_back("Access-Control-Allow-Methods", "GET, OPTIONS");
    reply.headers.emplace_back("Access-Control-Allow-Headers", "*");
    reply.headers.emplace_back("Access-Control-Max-Age", "86400");
    return reply;
  }
  std::map<std::string, std::string> params;
  try {
    params = decode_query_string(request.query);
  } catch (const sdk::Error& e) {
    return refused(400, e.code(), e.what(), count);
  }
  const auto q = params.find("q");
  const auto id = params.find("sessionId");
  if (q == params.end())
    return refused(400, "missing_field", "missing parameter 'q' (the command)", count);
  if (id == params.end() || !valid_session_id(id->second))
    return refused(400, "bad_request",
                   "parameter 'sessionId' must be 1 to 128 printable ASCII characters "
                   "without spaces",
                   count);

  SempreCommand command;
  try {
    command = parse_sempre_command(q->second);
  } catch (const sdk::Error& e) {
    return refused(400, e.code(), e.what(), count);
  }
  return api_.with_kernel([&](Kernel& kernel) {
    SempreSession* s = session_for(kernel, id->second);
    if (s == nullptr)
      return refused(503, "too_many_sessions",
                     "the server has " + std::to_string(max_sessions_) +
                         " /sempre sessions in use (serve.max_sessions); try later",
                     count);
    kernel.host->activate(*s->session);
    HttpReply reply;
    cors(reply);
    const auto start = std::chrono::steady_clock::now();
    SempreAnswer answer;
    std::string code;
    try {
      answer = run_sempre_command(*s, command);
    } catch (const sdk::Error& e) {
      answer = {};
      answer.lines.push_back(e.what());
      code = e.code();
    } catch (const std::exception& e) {
      answer = {};
      answer.lines.push_back(std::string("internal error: ") + e.what());
      code = sdk::codes::kInternal;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    reply.body = body(command.name, count, seconds, answer, code);
    return reply;
  });
}

}  // namespace flipper::studio
