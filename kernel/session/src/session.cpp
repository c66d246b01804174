// The session: op table, request/answer framing, and the state ops (world, user, state).
#include "flipper/kernel/session.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>

#include "flipper/kernel/protocol.hpp"
#include "flipper/kernel/session_request.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/config/regular_file.hpp"
#include "flipper/toolkit/json/json_writer.hpp"
#include "flipper/toolkit/json/raw_members.hpp"
#include "world_texts.hpp"

namespace flipper::kernel {

using toolkit::json::JsonWriter;

namespace {

// {"ok":false,"op":OP,"id":ID,"error":{"code","message"}}: op and id echoed from the request's
// text when it is at hand (object key order as sent), else from the tree.
// A deadline_exceeded error also names the limit that fired: "stopped" (docs/protocol.md).
void write_error(std::string& out, const Json* op, std::string_view op_text, const Json* id,
                 std::string_view id_text, const std::string& code, const std::string& message,
                 sdk::StopCause stopped = sdk::StopCause::none);

void write_echo(JsonWriter& w, const Json& value, std::string_view text, bool raw_float) {
  if (!text.empty())
    w.echo(text, raw_float);
  else
    w.value(value);
}

void write_error(std::string& out, const Json* op, std::string_view op_text, const Json* id,
                 std::string_view id_text, const std::string& code, const std::string& message,
                 sdk::StopCause stopped) {
  out.clear();
  JsonWriter w(out);
  w.begin_object().key("ok").boolean(false).key("op");
  if (op != nullptr)
    write_echo(w, *op, op_text, false);
  else
    w.null();
  if (id != nullptr) write_echo(w.key("id"), *id, id_text, true);
  w.key("error").begin_object().key("code").string(code).key("message").string(message);
  if (stopped != sdk::StopCause::none) w.key("stopped").string(sdk::to_string(stopped));
  w.end_object().end_object();
}

std::string error_line(const std::string& code, const std::string& message) {
  std::string out;
  write_error(out, nullptr, {}, nullptr, {}, code, message);
  return out;
}

}  // namespace

Session::Session(const std::shared_ptr<Runtime>& runtime, Extensions extensions)
    : Session(runtime, SessionOptions::from_config(runtime->config), std::move(extensions)) {}

Session::Session(std::shared_ptr<Runtime> runtime, SessionOptions options, Extensions extensions)
    : runtime_(std::move(runtime)),
      options_(options),
      executor_(runtime_->planner, options_.limits),
      world_(runtime_->default_world),
      texts_(std::make_unique<WorldTexts>(
          [this]() -> const PluginRef<sdk::World>& { return runtime_->world; })) {
  runtime_extensions_ = std::move(extensions);
  attach_all();
}

Session::~Session() = default;

void Session::install_default_ops() {
  set_op("hello", [](Session& s, const Json& r, JsonWriter& a) { s.op_hello(r, a); });
  set_op("world", [](Session& s, const Json& r, JsonWriter& a) { s.op_world(r, a); });
  set_op("user", [](Session& s, const Json& r, JsonWriter& a) {
    s.set_user(request::require_string(r, "name", "the user's name"));
    a.key("name").string(s.user());
  });
  set_op("state", [](Session& s, const Json&, JsonWriter& a) {
    s.write_world_version(a, s.world(), true);  // a client may ask for the state to resync
    s.write_changed_world(a.key("world"), s.world());
  });
  set_op("query", [](Session& s, const Json& r, JsonWriter& a) { s.op_query(r, a); });
  set_op("accept", [](Session& s, const Json& r, JsonWriter& a) { s.op_accept(r, a); });
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

void Session::attach_all() {
  ops_.clear();
  events_.clear();
  install_default_ops();
  for (const auto* list : {&runtime_extensions_, &own_extensions_})
    for (const auto& e : *list) e->attach(*this);
}

void Session::rebind(std::shared_ptr<Runtime> runtime, Extensions extensions) {
  runtime_ = std::move(runtime);
  executor_ = Executor(runtime_->planner, options_.limits);
  runtime_extensions_ = std::move(extensions);
  attach_all();
}

void Session::install(std::shared_ptr<SessionExtension> extension) {
  extension->attach(*this);
  own_extensions_.push_back(std::move(extension));
}

std::function<bool(const sdk::Rule&)> Session::visible_rules() const {
  std::function<bool(const sdk::Rule&)> filter;
  events_.emit(VisibilityAsked{user_, filter});
  return filter;
}

namespace {
class FunctionExtension final : public SessionExtension {
 public:
  explicit FunctionExtension(std::function<void(Session&)> attach) : attach_(std::move(attach)) {}
  void attach(Session& session) override { attach_(session); }

 private:
  std::function<void(Session&)> attach_;
};
}  // namespace

std::shared_ptr<SessionExtension> make_extension(std::function<void(Session&)> attach) {
  return std::make_shared<FunctionExtension>(std::move(attach));
}

void Session::set_world(sdk::WorldState world) {
  world_ = std::move(world);
  last_query_.reset();
  events_.emit(WorldReplaced{*this});
}

void Session::set_user(std::string name) {
  if (name.empty()) throw sdk::Error(sdk::codes::kBadRequest, "field 'name' must not be empty");
  user_ = std::move(name);
  events_.emit(UserChanged{*this, user_});
}

Json Session::world_json(const sdk::WorldState& state) const {
  return Json::parse(world_text(state));
}

const std::string& Session::world_text(const sdk::WorldState& state) const {
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

void Session::write_changed_world(JsonWriter& w, const sdk::WorldState& state) {
  if (protocol_ < 2)
    w.raw(world_text(state));
  else
    w.raw(texts_->changes(state));
}

void Session::write_world_version(JsonWriter& w, const sdk::WorldState& state, bool always) {
  if (protocol_ < 2 || !state.geometry) return;
  const std::uint64_t v = texts_->version(state);
  w.key("world_version").unsigned_integer(v);
  const bool sent =
      std::find(sent_versions_.begin(), sent_versions_.end(), v) != sent_versions_.end();
  if (sent && !always) return;
  w.key("geometry").raw(texts_->geometry(state));
  if (!sent) sent_versions_.push_back(v);
}

std::string Session::line_too_long(std::uint64_t bytes) const {
  return error_line(sdk::codes::kInputTooLong, "the request line has " + std::to_string(bytes) +
                                                   " bytes; the limit is input.max_line_bytes = " +
                                                   std::to_string(options_.input.max_line_bytes));
}

void Session::begin_call() {
  if (in_request_) return;
  request_stop_ =
      sdk::StopCondition::within_cpu(options_.input.cpu_budget, options_.input.deadline);
  request_charge_.attach(request_stop_);  // on the thread of this request
}

void Session::check_deadline(const char* stage) const {
  switch (const sdk::StopCause cause = request_stop_.cause()) {
    case sdk::StopCause::none:
      return;
    case sdk::StopCause::cpu_budget:
      throw sdk::StoppedError(cause, std::string("deadline exceeded while ") + stage +
                                         ": the request used more than session.cpu_budget_ms = " +
                                         std::to_string(options_.input.cpu_budget.count()) +
                                         " ms of CPU time (stopped: cpu_budget)");
    case sdk::StopCause::wall_backstop:
    case sdk::StopCause::cancelled:
      throw sdk::StoppedError(cause, std::string("deadline exceeded while ") + stage +
                                         ": the request took longer than session.deadline_ms = " +
                                         std::to_string(options_.input.deadline.count()) +
                                         " ms, the wall-clock backstop (stopped: wall_backstop)");
  }
}

std::string Session::handle_line(std::string_view line) {
  if (line.find_first_not_of(" \t\r\n") == std::string_view::npos) return {};  // blank
  try {
    if (line.size() > options_.input.max_line_bytes) return line_too_long(line.size());
    // Nesting is checked before parsing: the tree of a deeply nested value is copied and
    // destroyed recursively, and no request needs more than a few levels.
    const int limit = options_.input.max_json_depth;
    if (int depth = toolkit::json::json_depth(line, limit); depth > limit)
      return error_line(sdk::codes::kTooDeep,
                        "the request is nested deeper than input.max_json_depth = " +
                            std::to_string(limit) + " levels");
    Json request;
    try {
      // A world object is read by its plugin from the line's text (op_world): the tree keeps it
      // empty, so its walls and items are not built into nodes only to be freed.
      bool world_key = false, in_world = false;
      request = Json::parse(line, [&](int depth, Json::parse_event_t event, const Json& parsed) {
        if (depth != 1) return depth < 2 || !in_world;
        if (event == Json::parse_event_t::key)
          world_key = parsed == "world";
        else if (event == Json::parse_event_t::object_start)
          in_world = std::exchange(world_key, false);
        else
          in_world = world_key = false;
        return true;
      });
    } catch (const Json::exception& e) {
      // Syntax errors and numbers beyond double range (1e999); nlohmann's message carries the
      // byte position and may quote bytes that are not UTF-8 (the writer replaces them).
      return error_line(session_codes::kBadJson,
                        std::string("the line is not valid JSON: ") + e.what());
    }
    std::string out;
    answer(request, line, out);
    return out;
  } catch (const std::exception& e) {
    return error_line(sdk::codes::kInternal, std::string("internal error: ") + e.what());
  }
}

Json Session::handle(const Json& request) {
  std::string out;
  try {
    answer(request, {}, out);
  } catch (const std::exception& e) {
    out = error_line(sdk::codes::kInternal, std::string("internal error: ") + e.what());
  }
  return Json::parse(out);
}

void Session::answer(const Json& request, std::string_view line, std::string& out) {
  in_request_ = false;
  begin_call();
  if (!request.is_object())
    return write_error(out, nullptr, {}, nullptr, {}, session_codes::kBadJson,
                       "a request must be a JSON object, got " + std::string(request.type_name()));
  const Json* op = nullptr;
  const Json* id = nullptr;
  if (auto it = request.find("op"); it != request.end()) op = &*it;
  if (auto it = request.find("id"); it != request.end()) id = &*it;
  // Echoed from the line when the tree would not give the bytes sent: an id such as a 25-digit
  // number or 1.10, and an object's key order (the tree sorts keys).
  auto echo_text = [&](const Json* v, const char* key) {
    return v != nullptr && !line.empty() && (v->is_structured() || v->is_number_float())
               ? toolkit::json::top_level_value(line, key)
               : std::string_view();
  };
  const std::string_view op_text = echo_text(op, "op");
  const std::string_view id_text = echo_text(id, "id");
  auto refuse = [&](const std::string& code, const std::string& message,
                    sdk::StopCause stopped = sdk::StopCause::none) {
    write_error(out, op, op_text, id, id_text, code, message, stopped);
  };
  if (op == nullptr || op->is_null())
    return refuse(session_codes::kMissingField, "missing field 'op' (the operation to perform)");
  if (!op->is_string()) return refuse(sdk::codes::kBadRequest, "field 'op' must be a string");
  const std::string& name = op->get_ref<const std::string&>();
  auto handler = ops_.find(name);
  if (handler == ops_.end()) {
    std::string known;
    for (const auto& [n, h] : ops_) known += (known.empty() ? "" : ", ") + n;
    return refuse(session_codes::kUnknownOp,
                  "unknown op '" + name + "' (known ops: " + known + ")");
  }
  struct InRequest {  // the typed calls of the op keep the request's deadline
    Session& s;
    explicit InRequest(Session& session) : s(session) { s.in_request_ = true; }
    ~InRequest() {
      s.in_request_ = false;
      s.line_ = {};
    }
  } scope(*this);
  line_ = line;
  std::string code;  // of a refusal
  try {
    JsonWriter w(out);
    w.begin_object().key("ok").boolean(true).key("op").string(name);
    if (id != nullptr) write_echo(w.key("id"), *id, id_text, true);
    handler->second(*this, request, w);
    w.end_object();
  } catch (const sdk::Error& e) {
    refuse(code = e.code(), e.what(), sdk::stop_cause_of(e));
  } catch (const Json::exception& e) {
    refuse(code = sdk::codes::kBadRequest, std::string("bad request: ") + e.what());
  } catch (const std::exception& e) {
    refuse(code = sdk::codes::kInternal, std::string("internal error: ") + e.what());
  }
  events_.emit(RequestAnswered{name, code});
}

void Session::op_hello(const Json& req, JsonWriter& a) {
  if (auto p = request::optional_int(req, "protocol", "the protocol version to speak")) {
    if (*p != 1 && *p != 2)
      throw sdk::Error(sdk::codes::kBadRequest,
                       "protocol " + std::to_string(*p) + " is not supported (supported: 1, 2)");
    protocol_ = static_cast<int>(*p);
    sent_versions_.clear();  // a protocol-2 client is sent every geometry it will need
  }
  a.key("protocol").integer(protocol_).key("protocols").raw("[1,2]");
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

const sdk::WorldState& Session::open_world_text(const std::string& text, const std::string& base) {
  begin_call();
  sdk::WorldState state = load_requested_world(text, base);
  check_deadline("loading the world");
  set_world(std::move(state));
  return world_;
}

const sdk::WorldState& Session::open_world_file(const std::string& file) {
  begin_call();
  std::filesystem::path path(file);
  // Relative paths: the caller's directory first, then the config's.
  std::error_code ec;
  if (path.is_relative() && !std::filesystem::exists(path, ec))
    path = runtime_->config.resolve_path(file);
  std::string text = toolkit::config::read_regular_file(
      path.string(), options_.input.max_file_bytes, "world file", sdk::codes::kBadWorld);
  return open_world_text(text, path.parent_path().string());
}

void Session::op_world(const Json& req, JsonWriter& a) {
  auto world_field = req.find("world");
  if (world_field != req.end() && !world_field->is_null()) {
    if (!world_field->is_object())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'world' must be a world object");
    // The object's text as sent when the line is at hand: no second serialisation.
    std::string_view raw =
        line_.empty() ? std::string_view() : toolkit::json::top_level_value(line_, "world");
    std::string text = !raw.empty() && raw.front() == '{' ? std::string(raw) : world_field->dump();
    open_world_text(text, std::filesystem::current_path().string());
  } else {
    open_world_file(
        request::require_string(req, "file", "a world object 'world' or a path 'file'"));
  }
  write_world_version(a, world_);
  write_changed_world(a.key("world"), world_);
}

}  // namespace flipper::kernel
