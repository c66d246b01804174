#pragma once
/// @file session.hpp
/// One protocol session (docs/protocol.md): the runtime, the current world and user, and the
/// last query's full parse result.
///
/// Two faces over one implementation:
/// - the typed query service (query_service.hpp): `query`, `accept`, `open_world_file`,
///   `set_user`, `set_world`; `flipper run`, `repl` and `replay` call these directly;
/// - the protocol: `handle_line` turns one request line into exactly one answer line. Ops are
///   looked up in a table; each JSON op is a thin adapter that reads the request's fields, calls
///   the typed service and writes the result with a toolkit::json::JsonWriter.
/// Modules above the kernel come in as extensions (session_extension.hpp): ops and typed events.
/// @code
///   session.install(kernel::make_extension([&](Session& s) {
///     s.set_op("define", [&](Session& s, const Json& req, toolkit::json::JsonWriter& answer) { ...
///     }); s.on<Accepting>([&](const Accepting& e) { /* persist */ });
///   }));
/// @endcode
/// A handler writes the answer's payload members into the open answer object; the session has
/// written `ok`, `op` and `id` before and closes it after. A handler reports a refusal by
/// throwing sdk::Error(code, message) and must leave the state unchanged then (what it wrote is
/// discarded).

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/query_service.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/kernel/session_extension.hpp"
#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/world.hpp"
#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::kernel {

class WorldTexts;

/// Requests as parsed. Answers are written with a toolkit::json::JsonWriter (field order as
/// written), so the tree's key order never reaches a client.
using Json = nlohmann::json;

/// Protocol error codes owned by the session (sdk::codes has the shared ones).
namespace session_codes {
inline constexpr const char* kBadJson = "bad_json";
inline constexpr const char* kUnknownOp = "unknown_op";
inline constexpr const char* kMissingField = "missing_field";
inline constexpr const char* kNoQuery = "no_query";
inline constexpr const char* kRankOutOfRange = "rank_out_of_range";
inline constexpr const char* kNotAcceptable = "not_acceptable";
}  // namespace session_codes

/// Settings the session reads from the config once, at construction.
struct SessionOptions {
  int k = static_cast<int>(keys::kSessionK.def);  ///< session.k: candidates shown per query
  std::size_t max_chars = static_cast<std::size_t>(keys::kMaxChars.def);  ///< input.max_chars
  /// input.max_semicolons: refused at this many `;` tokens
  int max_semicolons = static_cast<int>(keys::kMaxSemicolons.def);
  int beam = 0;       ///< parser beam (0: the parser's default)
  ExecLimits limits;  ///< execution.*
  InputLimits input;  ///< input.max_*, world.max_cells, session.deadline_ms
  static SessionOptions from_config(const Config& config);
};

class Session {
 public:
  using OpHandler =
      std::function<void(Session&, const Json& request, toolkit::json::JsonWriter& answer)>;
  using Extensions = std::vector<std::shared_ptr<SessionExtension>>;

  /// Options from the runtime's config; `extensions` belong to the runtime (rebind replaces
  /// them with the next runtime's) and are attached in order.
  explicit Session(const std::shared_ptr<Runtime>& runtime, Extensions extensions = {});
  Session(std::shared_ptr<Runtime> runtime, SessionOptions options, Extensions extensions = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // ---- the typed query service (query_service.hpp) ----

  /// Parses `text`, ranks the readings and runs the first k on the current world. Throws
  /// sdk::Error: input_too_long (input.max_chars code points, input.max_semicolons, max_tokens),
  /// bad_request (negative k), deadline_exceeded, plugin errors. The query becomes the last one.
  QueryResult query(const QueryRequest& request);
  /// Accepts a shown candidate of the last query: the scorer learns, use counters count, the
  /// accept hook persists, then the world becomes the candidate's. Throws no_query,
  /// rank_out_of_range, not_acceptable, or the hook's error (then nothing changed).
  /// `before_commit` sees the outcome before anything is applied (the protocol op writes its
  /// answer there: nothing may fail after the commit).
  AcceptResult accept(const AcceptRequest& request,
                      const std::function<void(const sdk::Outcome&)>& before_commit = {});
  /// Loads a world file (relative: the caller's directory first, then the config's) and makes it
  /// the current world. Throws bad_world.
  const sdk::WorldState& open_world_file(const std::string& file);
  /// Loads a world object's text (relative paths in it: from `base`) and makes it current.
  const sdk::WorldState& open_world_text(const std::string& text, const std::string& base);
  /// Replaces the current world (and forgets the last query, whose plans no longer apply).
  void set_world(sdk::WorldState world);
  /// Makes `name` the current user (bad_request when empty) and emits UserChanged.
  void set_user(std::string name);

  // ---- the protocol (docs/protocol.md) ----

  /// One request line -> one answer line (no trailing newline). Empty (blank) lines give an empty
  /// string: no answer. Never throws. Lines longer than input.max_line_bytes or nested deeper
  /// than input.max_json_depth are refused before they are parsed.
  std::string handle_line(std::string_view line);
  /// The answer to a line a front end did not keep because it was longer than
  /// input.max_line_bytes (`bytes` read so far, at least the limit + 1).
  std::string line_too_long(std::uint64_t bytes) const;
  /// The same for an already parsed request, the answer parsed again (for tests and in-process
  /// callers that want a tree). Never throws.
  Json handle(const Json& request);

  /// The time limits of the request being handled, from when it arrived (or when a typed call
  /// began, outside a request): session.cpu_budget_ms of this thread's CPU time and the
  /// wall-clock backstop session.deadline_ms (docs/planners.md §2). Parses and executions of the
  /// request stop at it.
  const sdk::StopCondition& request_stop() const { return request_stop_; }
  /// Starts the limits of a typed call made outside a protocol request (a define called by a
  /// front end); inside a request it keeps the request's.
  void begin_call();
  /// Throws sdk::StoppedError(deadline_exceeded, cpu_budget | wall_backstop) naming `stage` when
  /// one of the request's limits has fired.
  void check_deadline(const char* stage) const;
  /// Throws sdk::Error(input_too_long) when `text` has more than input.max_chars code points.
  void check_length(std::string_view text) const;

  // ---- extensions (session_extension.hpp) ----

  /// Installs or replaces an op (from an extension's attach: a direct call lasts until rebind).
  void set_op(const std::string& name, OpHandler handler);
  /// The current handler of an op (to wrap it), or null.
  const OpHandler* find_op(const std::string& name) const;
  std::vector<std::string> op_names() const;
  /// Subscribes to an event (from an extension's attach, like set_op).
  template <class Event>
  void on(std::function<void(const Event&)> handler) {
    events_.on<Event>(std::move(handler));
  }
  /// Tells the subscribers of an event (an extension's own events too).
  template <class Event>
  void emit(const Event& event) const {
    events_.emit(event);
  }
  /// Attaches an extension of the session's own and keeps it across rebinds (after the
  /// runtime's extensions); find it again with extension<T>().
  void install(std::shared_ptr<SessionExtension> extension);
  /// The extension of type T (the runtime's or the session's own), or null.
  template <class T>
  T* extension() const {
    for (const auto* list : {&runtime_extensions_, &own_extensions_})
      for (const auto& e : *list)
        if (auto* t = dynamic_cast<T*>(e.get())) return t;
    return nullptr;
  }
  /// Moves the session onto another runtime of the same config (another kernel over the same
  /// lexicon store, as a server's kernel pool has: docs/studio.md §5) with that runtime's
  /// extensions. What the client sees stays: the world, user, last query, protocol and the world
  /// versions sent. The op table and subscriptions are built again: the defaults, the runtime's
  /// extensions, then the session's own, each attached in the order it was installed.
  void rebind(std::shared_ptr<Runtime> runtime, Extensions extensions);
  /// Emits Activated: call before handling a request when sessions share extensions.
  void activate() const { events_.emit(Activated{*this}); }

  Runtime& runtime() { return *runtime_; }
  const Runtime& runtime() const { return *runtime_; }
  const SessionOptions& options() const { return options_; }
  const Executor& executor() const { return executor_; }

  const sdk::WorldState& world() const { return world_; }
  const std::string& user() const { return user_; }
  /// Null before the first query, after an accept and after a world change.
  const LastQuery* last_query() const { return last_query_.get(); }
  /// Parses `tokens` as a query of the current user is parsed (the scorer, the rules visible to
  /// the user, the beam, the request's limits), with the chart of every sub-span when
  /// `want_chart`; a parse the limits stopped throws deadline_exceeded naming `stage`.
  sdk::ParseResult parse(const std::vector<std::string>& tokens, bool want_chart,
                         const char* stage);
  /// The rule filter for the current user (null when every rule is visible).
  std::function<bool(const sdk::Rule&)> visible_rules() const;

  /// The world object of a state as answers carry it: the world plugin's text (one line), from
  /// its static text per world version and the plugin's items and robot parts (world_texts.hpp).
  /// The last few are cached (candidates often end in the same world).
  const std::string& world_text(const sdk::WorldState& state) const;
  /// world_text as a tree, for callers that inspect it (the text is parsed on each call).
  Json world_json(const sdk::WorldState& state) const;
  /// The protocol version the client asked for with `hello` (docs/protocol.md § "Protocol
  /// versions"); 1 by default.
  int protocol() const { return protocol_; }
  /// Writes the value of a world that changed: in protocol 1 the full world object, in protocol 2
  /// only `{"items", "robot"}` (then write_world_version() must be called for the answer).
  void write_changed_world(toolkit::json::JsonWriter& w, const sdk::WorldState& state);
  /// Protocol 2: writes the member "world_version" (the id of the state's geometry and rooms),
  /// and "geometry" (the world object without items and robot) when this client has not been
  /// sent that version yet or `always` is set. Protocol 1: writes nothing.
  void write_world_version(toolkit::json::JsonWriter& w, const sdk::WorldState& state,
                           bool always = false);

 private:
  struct CachedWorld {
    sdk::WorldState state;
    std::string text;
  };
  /// The answer to a parsed request, written to `out`; `line` is its text (empty when the
  /// request did not come as a line): `op` and `id` are echoed from it.
  void answer(const Json& request, std::string_view line, std::string& out);

  void install_default_ops();
  sdk::WorldState load_requested_world(const std::string& text, const std::string& base);
  void op_hello(const Json& request, toolkit::json::JsonWriter& answer);
  void op_world(const Json& request, toolkit::json::JsonWriter& answer);
  void op_query(const Json& request, toolkit::json::JsonWriter& answer);
  void op_accept(const Json& request, toolkit::json::JsonWriter& answer);
  void attach_all();

  std::shared_ptr<Runtime> runtime_;
  SessionOptions options_;
  Executor executor_;
  sdk::WorldState world_;
  std::string user_ = "anonymous";
  std::shared_ptr<LastQuery> last_query_;
  std::map<std::string, OpHandler, std::less<>> ops_;
  Extensions runtime_extensions_, own_extensions_;
  EventBus events_;
  std::uint64_t accepted_plans_ = 0;
  mutable std::vector<CachedWorld> world_cache_;  // most recent first
  std::unique_ptr<WorldTexts> texts_;             // world texts by version (world_texts.hpp)
  struct LoadedWorld {                            // a world op's input and what it loaded
    std::string base, text;
    sdk::WorldState state;
  };
  std::vector<LoadedWorld> loaded_;  // the last few, most recent first
  int protocol_ = 1;
  std::vector<std::uint64_t> sent_versions_;  // protocol 2: versions whose geometry was sent
  std::string_view line_;                     // the request line being handled (handle_line)
  bool in_request_ = false;                   // a protocol request is being handled
  sdk::StopCondition request_stop_;  // begin_call: the request's CPU budget and wall backstop
  CpuCharge request_charge_;         // isolated plugin calls' CPU time counts against request_stop_
};

}  // namespace flipper::kernel
