// GET /sempre: transport, sessions and answers (see sempre.hpp; docs/sempre.md).
#include "sempre.hpp"

#include <cctype>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/json/json_writer.hpp"
#include "studio_ops.hpp"

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

// `allow`: the Access-Control-Allow-Origin ("" none).
void cors(HttpReply& reply, const std::string& allow) {
  if (!allow.empty()) {
    reply.headers.emplace_back("Access-Control-Allow-Origin", allow);
    reply.headers.emplace_back("Vary", "Origin");
  }
  reply.headers.emplace_back("Cache-Control", "no-store");
}

std::string lower_origin(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

// The members in nlohmann's (sorted) key order: the bytes dumping the answer's tree wrote.
std::string sempre_body(const std::string& type, std::uint64_t count, double seconds,
                        const SempreAnswer& a, const std::string& error_code) {
  Json stats = a.stats;
  stats["type"] = type;
  stats["count"] = count;
  stats["walltime"] = seconds;
  std::size_t size = 64;
  for (const auto& c : a.candidates) size += c.size() + 1;
  std::string out;
  out.reserve(size);
  toolkit::json::JsonWriter w(out);
  w.begin_object().key("candidates").begin_array();
  for (const auto& c : a.candidates) w.raw(c);
  w.end_array();
  if (!error_code.empty()) {
    w.key("error").begin_object().key("code").string(error_code);
    w.key("message").string(a.lines.empty() ? "" : a.lines[0]).end_object();
  }
  w.key("lines").begin_array();
  for (const auto& l : a.lines) w.string(l);
  w.end_array().key("stats").value(stats).end_object();
  return out;
}

namespace {

HttpReply refused(int status, const std::string& code, const std::string& message,
                  std::uint64_t count, const std::string& allow) {
  HttpReply reply;
  cors(reply, allow);
  reply.status = status;
  SempreAnswer a;
  a.lines.push_back(message);
  reply.body = sempre_body("error", count, 0.0, a, code);
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

SempreEndpoint::SempreEndpoint(Sessions& sessions, const ServeOptions& options)
    : sessions_(sessions), origins_(options.sempre_origins) {}

std::optional<std::string> SempreEndpoint::allowed_origin(const SempreRequest& r) const {
  // A listed origin (or "*": every origin, the original's behaviour) is answered with its CORS
  // header; the server's own page and programs need none; any other browser request is refused
  // before it does anything: CORS only hides an answer, the GET (a :def) would still run.
  for (const auto& o : origins_) {
    if (o == "*") return r.origin.empty() ? std::string("*") : r.origin;
    if (!r.origin.empty() && lower_origin(o) == lower_origin(r.origin)) return r.origin;
  }
  if (r.own_origin) return std::string();
  return std::nullopt;
}

SempreEndpoint::Slot* SempreEndpoint::slot_for(Kernel& kernel, const std::string& id,
                                               const std::string& peer,
                                               std::optional<SessionRegistry::Refusal>& refusal) {
  SessionRegistry& registry = sessions_.registry();
  const auto now = Clock::now();
  auto it = slots_.find(id);
  // Evicted by the registry (idle, or for memory): the sessionId starts afresh.
  if (it != slots_.end() && registry.find(it->second.entry->token) != it->second.entry) {
    slots_.erase(it);
    it = slots_.end();
  }
  if (it == slots_.end()) {
    if ((refusal = registry.admit_new(peer, now))) return nullptr;
    if (slots_.size() >= 2 * registry.limits().max_sessions)  // drop the evicted ones
      std::erase_if(slots_, [&](const auto& e) {
        return registry.find(e.second.entry->token) != e.second.entry;
      });
    auto entry = std::make_shared<SessionEntry>();
    entry->address = peer;
    entry->user = sempre_user(id);
    entry->kernel = &kernel;
    entry->session = kernel.host->open();
    entry->session->set_user(entry->user);
    registry.add(entry, now);
    Slot slot;
    slot.entry = entry;
    slot.state.session = entry->session.get();
    SessionEntry* raw = entry.get();
    const std::size_t most = kernel.max_world_bytes;
    const std::size_t base = registry.limits().session_base_bytes;
    slot.state.reserve_world = [&registry, raw, most] {
      return registry.reserve(*raw, most, Clock::now());
    };
    slot.state.charge_world = [&registry, raw, base] {
      const auto& geometry = raw->session->world().geometry;
      registry.charge(*raw, base + (geometry ? world_bytes(geometry->cell_count()) : 0));
    };
    it = slots_.emplace(id, std::move(slot)).first;
  }
  return &it->second;
}

HttpReply SempreEndpoint::handle(const SempreRequest& request) {
  const std::uint64_t count = ++count_;
  const std::optional<std::string> allow = allowed_origin(request);
  if (!allow)
    return refused(403, "cross_origin",
                   "/sempre answers this server's own page and the origins of "
                   "serve.sempre_origins only (Origin '" +
                       request.origin.substr(0, 200) + "')",
                   count, std::string());
  if (request.method == "OPTIONS") {  // a pre-flight of an allowed origin
    HttpReply reply;
    cors(reply, *allow);
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
    return refused(400, e.code(), e.what(), count, *allow);
  }
  const auto q = params.find("q");
  const auto id = params.find("sessionId");
  if (q == params.end())
    return refused(400, "missing_field", "missing parameter 'q' (the command)", count, *allow);
  if (id == params.end() || !valid_session_id(id->second))
    return refused(400, "bad_request",
                   "parameter 'sessionId' must be 1 to 128 printable ASCII characters "
                   "without spaces",
                   count, *allow);

  SempreCommand command;
  try {
    command = parse_sempre_command(q->second);
  } catch (const sdk::Error& e) {
    return refused(400, e.code(), e.what(), count, *allow);
  }
  sessions_.bury_evicted();  // sessions the registry evicted, destroyed under their kernel's lock
  return sessions_.with_kernel([&](Kernel& kernel) {
    std::optional<SessionRegistry::Refusal> refusal;
    Slot* slot = slot_for(kernel, id->second, request.peer, refusal);
    if (slot == nullptr)
      return refused(refusal->status, refusal->code, refusal->message, count, *allow);
    SessionRegistry& registry = sessions_.registry();
    if (!registry.admit(*slot->entry, Clock::now()))
      return refused(429, "rate_limited",
                     "too many requests in this session (serve.rate_per_second)", count, *allow);
    // Running: never evicted meanwhile.
    registry.set_busy(*slot->entry, true);
    struct Idle {
      SessionRegistry& registry;
      SessionEntry& entry;
      ~Idle() { registry.set_busy(entry, false); }
    } idle{registry, *slot->entry};
    SempreSession* s = &slot->state;
    s->session->activate();
    HttpReply reply;
    cors(reply, *allow);
    const auto start = std::chrono::steady_clock::now();
    SempreAnswer answer;
    std::string code;
    try {
      answer = run_sempre_command(*s, command);
    } catch (const sdk::Error& e) {
      answer = {};
      answer.lines.push_back(without_paths(e.what()));
      code = e.code();
    } catch (const std::exception& e) {
      answer = {};
      answer.lines.push_back("internal error: " + without_paths(e.what()));
      code = sdk::codes::kInternal;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    reply.body = sempre_body(command.name, count, seconds, answer, code);
    return reply;
  });
}

}  // namespace flipper::studio
