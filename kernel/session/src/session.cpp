// The session: op table, request/answer framing, and the state ops (world, user, state).
#include "flipper/kernel/session.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "flipper/kernel/protocol.hpp"
#include "flipper/kernel/session_request.hpp"
#include "flipper/sdk/errors.hpp"
#include "world_texts.hpp"

namespace flipper::kernel {
namespace {

Json error_answer(const Json* op, const Json* id, const std::string& code,
                  const std::string& message) {
  Json a;
  a["ok"] = false;
  a["op"] = op != nullptr ? *op : Json(nullptr);
  if (id != nullptr) a["id"] = *id;
  a["error"] = Json{{"code", code}, {"message", message}};
  return a;
}

// Answers are dumped with invalid UTF-8 replaced (U+FFFD): a message may quote the request's bytes.
std::string dump_answer(const Json& answer) {
  return answer.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// The text of the top-level "id" when it is a number: a 25-digit id or 1.10 must come back as
// sent, and the parsed double would not (nlohmann hands its SAX the number's raw text).
class RawIdSax : public nlohmann::json_sax<Json> {
 public:
  std::string raw;
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t& s) override {
    if (depth_ == 1 && in_id_) raw = s;
    return value();
  }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(); }
  bool key(string_t& k) override {
    in_id_ = depth_ == 1 && k == "id";
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 private:
  bool value() {
    if (depth_ == 1) in_id_ = false;
    return true;
  }
  bool open() {
    value();
    ++depth_;
    return true;
  }
  bool close() {
    --depth_;
    return true;
  }
  int depth_ = 0;
  bool in_id_ = false;
};

std::string raw_id_text(std::string_view line) {
  RawIdSax sax;
  Json::sax_parse(line, &sax);
  return sax.raw;
}

bool is_blank(std::string_view s) {
  for (char c : s)
    if (c != ' ' && c != '\t' && c != '\r' && c != '\n') return false;
  return true;
}

}  // namespace

Session::Session(std::shared_ptr<Runtime> runtime)
    : Session(runtime, SessionOptions::from_config(runtime->config)) {}

Session::Session(std::shared_ptr<Runtime> runtime, SessionOptions options)
    : runtime_(std::move(runtime)),
      options_(options),
      executor_(runtime_->planner, options_.limits),
      world_(runtime_->default_world),
      texts_(std::make_unique<WorldTexts>([this](const sdk::WorldState& state) {
        std::string text =
            runtime_->world.call("save", [&](const sdk::World& w) { return w.save(state); });
        // The answer is one line: normalise a plugin that writes multi-line text.
        if (text.find('\n') != std::string::npos) text = nlohmann::json::parse(text).dump();
        return text;
      })) {
  // A control character and a random tag: no request value can collide with a placeholder.
  std::random_device rd;
  marker_ = "\x01w" + std::to_string(rd()) + std::to_string(rd()) + ":";
  install_default_ops();
}

Session::~Session() = default;

void Session::install_default_ops() {
  set_op("hello", [](Session& s, const Json& r) { return s.op_hello(r); });
  set_op("world", [](Session& s, const Json& r) { return s.op_world(r); });
  set_op("user", [](Session& s, const Json& r) { return s.op_user(r); });
  set_op("state", [](Session& s, const Json& r) { return s.op_state(r); });
  set_op("query", [](Session& s, const Json& r) { return s.op_query(r); });
  set_op("accept", [](Session& s, const Json& r) { return s.op_accept(r); });
}

void Session::set_op(const std::string& name, OpHandler handler) {
  ops_[name] = std::move(handler);
}

const Session::OpHandler* Session::find_op(const std::string& name) const {
  auto it = ops_.find(name);
  return it == ops_.end() ? nullptr : &it->second;
}

std::vector<std::string> Session::op_names() const {
  std::vector<std::string> names;
  for (const auto& [name, handler] : ops_) names.push_back(name);
  return names;
}

std::function<bool(const sdk::Rule&)> Session::visible_rules() const {
  if (!visibility_) return {};
  return [hook = visibility_, user = user_](const sdk::Rule& r) { return hook(r, user); };
}

void Session::set_world(sdk::WorldState world) {
  world_ = std::move(world);
  last_query_.reset();
}

Json Session::world_json(const sdk::WorldState& state) const {
  std::string text =
      runtime_->world.call("save", [&](const sdk::World& w) { return w.save(state); });
  return Json::parse(text);
}

const std::string& Session::world_text(const sdk::WorldState& state) {
  for (std::size_t i = 0; i < world_cache_.size(); ++i)
    if (world_cache_[i].state.same_state(state)) {
      if (i != 0) std::swap(world_cache_[i], world_cache_[0]);
      return world_cache_[0].text;
    }
  std::string text = texts_->full(state);
  constexpr std::size_t kCacheSize = 8;
  if (world_cache_.size() == kCacheSize) world_cache_.pop_back();
  world_cache_.insert(world_cache_.begin(), CachedWorld{state, std::move(text)});
  return world_cache_[0].text;
}

Json Session::raw_json(std::string text) {
  if (!line_mode_) return Json::parse(text);
  spliced_.push_back(std::move(text));
  return marker_ + std::to_string(spliced_.size() - 1);
}

Json Session::answer_changed_world(const sdk::WorldState& state) {
  if (protocol_ < 2) return answer_world(state);
  return raw_json(texts_->changes(state));
}

void Session::add_world_version(Json& payload, const sdk::WorldState& state, bool always) {
  if (protocol_ < 2 || !state.geometry) return;
  const std::uint64_t v = texts_->version(state);
  payload["world_version"] = v;
  const bool sent =
      std::find(sent_versions_.begin(), sent_versions_.end(), v) != sent_versions_.end();
  if (sent && !always) return;
  payload["geometry"] = raw_json(texts_->geometry(state));
  if (!sent) sent_versions_.push_back(v);
}

Json Session::answer_world(const sdk::WorldState& state) {
  if (!line_mode_) return Json::parse(world_text(state));
  spliced_.push_back(world_text(state));
  return marker_ + std::to_string(spliced_.size() - 1);
}

Json Session::answer_trace(const std::vector<sdk::TraceStep>& trace, int dims) {
  if (!line_mode_) return protocol::trace_json(trace, dims);
  std::string text;
  text.reserve(trace.size() * 28 + 2);
  protocol::append_trace_text(text, trace, dims);
  spliced_.push_back(std::move(text));
  return marker_ + std::to_string(spliced_.size() - 1);
}

// Replaces each placeholder string ("\u0001w<tag>:<i>" once dumped) by world text i.
std::string Session::splice_worlds(std::string answer) const {
  if (spliced_.empty()) return answer;
  const std::string needle = "\"\\u0001" + marker_.substr(1);
  std::string out;
  out.reserve(answer.size() + spliced_.size() * (spliced_.front().size() + 8));
  std::size_t from = 0;
  for (std::size_t at = answer.find(needle); at != std::string::npos;
       at = answer.find(needle, from)) {
    out.append(answer, from, at - from);
    std::size_t digits = at + needle.size();
    std::size_t end = answer.find('"', digits);
    std::size_t index = std::stoul(answer.substr(digits, end - digits));
    out += spliced_.at(index);
    from = end + 1;
  }
  out.append(answer, from, std::string::npos);
  return out;
}

std::string Session::line_too_long(std::uint64_t bytes) const {
  return dump_answer(error_answer(nullptr, nullptr, sdk::codes::kInputTooLong,
                                  "the request line has " + std::to_string(bytes) +
                                      " bytes; the limit is input.max_line_bytes = " +
                                      std::to_string(options_.input.max_line_bytes)));
}

void Session::check_deadline(const char* stage) const {
  if (std::chrono::steady_clock::now() >= deadline_)
    throw sdk::Error(sdk::codes::kDeadlineExceeded,
                     std::string("deadline exceeded while ") + stage +
                         ": the request took longer than session.deadline_ms = " +
                         std::to_string(options_.input.deadline.count()));
}

std::string Session::handle_line(std::string_view line) {
  if (is_blank(line)) return {};
  line_mode_ = false;
  try {
    if (line.size() > options_.input.max_line_bytes) return line_too_long(line.size());
    // Nesting is checked before parsing: the tree of a deeply nested value is copied and
    // destroyed recursively, and no request needs more than a few levels.
    const int limit = options_.input.max_json_depth;
    if (int depth = json_depth(line, limit); depth > limit)
      return dump_answer(error_answer(nullptr, nullptr, sdk::codes::kTooDeep,
                                      "the request is nested deeper than input.max_json_depth = " +
                                          std::to_string(limit) + " levels"));
    Json request;
    try {
      request = Json::parse(line);
    } catch (const Json::exception& e) {
      // Syntax errors and numbers beyond double range (1e999); nlohmann's message carries the
      // byte position and may quote bytes that are not UTF-8 (dump_answer replaces them).
      return dump_answer(error_answer(nullptr, nullptr, session_codes::kBadJson,
                                      std::string("the line is not valid JSON: ") + e.what()));
    }
    spliced_.clear();
    if (request.is_object())
      if (auto id = request.find("id"); id != request.end() && id->is_number_float())
        if (std::string raw = raw_id_text(line); !raw.empty()) {
          spliced_.push_back(std::move(raw));
          *id = marker_ + std::to_string(spliced_.size() - 1);
        }
    line_mode_ = true;
    line_ = line;
    Json answer = handle(request);
    line_mode_ = false;
    line_ = {};
    return splice_worlds(dump_answer(answer));
  } catch (const std::exception& e) {
    line_mode_ = false;
    line_ = {};
    return dump_answer(error_answer(nullptr, nullptr, sdk::codes::kInternal,
                                    std::string("internal error: ") + e.what()));
  }
}

Json Session::handle(const Json& request) {
  deadline_ = options_.input.deadline.count() > 0
                  ? std::chrono::steady_clock::now() + options_.input.deadline
                  : std::chrono::steady_clock::time_point::max();
  if (!request.is_object())
    return error_answer(nullptr, nullptr, session_codes::kBadJson,
                        "a request must be a JSON object, got " + std::string(request.type_name()));
  const Json* op = nullptr;
  const Json* id = nullptr;
  if (auto it = request.find("op"); it != request.end()) op = &*it;
  if (auto it = request.find("id"); it != request.end()) id = &*it;
  if (op == nullptr || op->is_null())
    return error_answer(op, id, session_codes::kMissingField,
                        "missing field 'op' (the operation to perform)");
  if (!op->is_string())
    return error_answer(op, id, sdk::codes::kBadRequest, "field 'op' must be a string");
  const std::string& name = op->get_ref<const std::string&>();
  auto handler = ops_.find(name);
  if (handler == ops_.end()) {
    std::string known;
    for (const auto& [n, h] : ops_) known += (known.empty() ? "" : ", ") + n;
    return error_answer(op, id, session_codes::kUnknownOp,
                        "unknown op '" + name + "' (known ops: " + known + ")");
  }
  try {
    Json payload = handler->second(*this, request);
    Json answer;
    answer["ok"] = true;
    answer["op"] = *op;
    if (id != nullptr) answer["id"] = *id;
    for (auto& [key, value] : payload.items()) answer[key] = std::move(value);
    return answer;
  } catch (const sdk::Error& e) {
    return error_answer(op, id, e.code(), e.what());
  } catch (const Json::exception& e) {
    return error_answer(op, id, sdk::codes::kBadRequest, std::string("bad request: ") + e.what());
  } catch (const std::exception& e) {
    return error_answer(op, id, sdk::codes::kInternal, std::string("internal error: ") + e.what());
  }
}

Json Session::op_hello(const Json& req) {
  if (auto p = request::optional_int(req, "protocol", "the protocol version to speak")) {
    if (*p != 1 && *p != 2)
      throw sdk::Error(sdk::codes::kBadRequest,
                       "protocol " + std::to_string(*p) + " is not supported (supported: 1, 2)");
    protocol_ = static_cast<int>(*p);
    sent_versions_.clear();  // a protocol-2 client is sent every geometry it will need
  }
  return Json{{"protocol", protocol_}, {"protocols", Json::array({1, 2})}};
}

// The world a `world` request gives: loaded by the plugin, or the state loaded from the same text
// before (clients send the same map again and again), then bound to its world version.
sdk::WorldState Session::load_requested_world(const std::string& text, const std::string& base) {
  for (std::size_t i = 0; i < loaded_.size(); ++i)
    if (loaded_[i].text == text && loaded_[i].base == base) {
      if (i != 0) std::swap(loaded_[i], loaded_[0]);
      return loaded_[0].state;
    }
  sdk::WorldState state = load_world_text(*runtime_, text, base);  // guarded inside
  texts_->intern(state);
  constexpr std::size_t kKept = 2;
  if (loaded_.size() == kKept) loaded_.pop_back();
  loaded_.insert(loaded_.begin(), LoadedWorld{base, text, state});
  return state;
}

Json Session::op_world(const Json& req) {
  sdk::WorldState state;
  auto world_field = req.find("world");
  if (world_field != req.end() && !world_field->is_null()) {
    if (!world_field->is_object())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'world' must be a world object");
    const std::string base = std::filesystem::current_path().string();
    // The object's text as sent when the line is at hand: no second serialisation.
    std::string_view raw = line_.empty() ? std::string_view() : top_level_value(line_, "world");
    std::string text = !raw.empty() && raw.front() == '{' ? std::string(raw) : world_field->dump();
    state = load_requested_world(text, base);
  } else {
    std::string file =
        request::require_string(req, "file", "a world object 'world' or a path 'file'");
    std::filesystem::path path(file);
    // Relative paths: the caller's directory first, then the config's.
    std::error_code ec;
    if (path.is_relative() && !std::filesystem::exists(path, ec))
      path = runtime_->config.resolve_path(file);
    std::string text = read_regular_file(path.string(), options_.input.max_file_bytes, "world file",
                                         sdk::codes::kBadWorld);
    state = load_requested_world(text, path.parent_path().string());
  }
  check_deadline("loading the world");
  set_world(std::move(state));
  Json payload;
  add_world_version(payload, world_);
  payload["world"] = answer_changed_world(world_);
  return payload;
}

Json Session::op_user(const Json& req) {
  std::string name = request::require_string(req, "name", "the user's name");
  if (name.empty()) throw sdk::Error(sdk::codes::kBadRequest, "field 'name' must not be empty");
  user_ = name;
  return Json{{"name", std::move(name)}};
}

Json Session::op_state(const Json&) {
  Json payload;
  add_world_version(payload, world_, true);  // a client may ask for the state to resync
  payload["world"] = answer_changed_world(world_);
  return payload;
}

}  // namespace flipper::kernel
