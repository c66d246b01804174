#pragma once
/// @file session.hpp
/// One protocol session (docs/protocol.md): the runtime, the current world and user, and the
/// last query's full parse result. `handle_line` turns one request line into exactly one answer
/// line; every front end (`flipper session`, `flipper repl`, experiment runs) goes through it.
///
/// Ops are looked up in a table, so another module adds or replaces an op in one place:
/// @code
///   session.set_op("define", [&](Session& s, const Json& req) { ...; return Json{{"rules", ...}};
///   }); session.set_visibility([&](const sdk::Rule& r, const std::string& user) { ... });
///   session.set_on_accept([&](Session& s, const AcceptEvent& e) { /* persist weights, counters */
///   });
/// @endcode
/// A handler returns the answer's payload fields; the session adds `ok`, `op` and `id`. A handler
/// reports a refusal by throwing sdk::Error(code, message) and must leave the state unchanged then.

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/kernel/accepted_plan.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/limits.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::kernel {

class WorldTexts;

/// Requests and answers keep their field order ("ok", "op", "id" first).
using Json = nlohmann::ordered_json;

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

/// A candidate shown to the user, with what is needed to accept it.
struct ShownCandidate {
  std::size_t index = 0;                    ///< into LastQuery::parse.candidates
  sdk::DerivationPtr derivation;            ///< the derivation whose rules are reported/credited
  std::vector<sdk::RulePtr> induced_rules;  ///< distinct induced rules of that derivation
  sdk::Outcome outcome;                     ///< executed on the world of the query
  std::optional<std::string> error_code;    ///< set when the candidate cannot be accepted
};

/// The last query: everything learning and definitions need.
struct LastQuery {
  std::string text;
  std::vector<std::string> tokens;
  std::string user;
  sdk::ParseResult parse;     ///< all candidates with every derivation
  std::vector<double> probs;  ///< softmax over all candidates' scores
  std::vector<ShownCandidate> shown;
  sdk::WorldState world;  ///< the world the query was answered in
};

/// What an accept did, for the naturalization module's persistence hook.
struct AcceptEvent {
  const LastQuery& query;
  std::size_t rank;
  const ShownCandidate& candidate;
  const sdk::Outcome& outcome;
  const std::string& user;
};

class Session {
 public:
  using OpHandler = std::function<Json(Session&, const Json& request)>;
  using VisibilityHook = std::function<bool(const sdk::Rule&, const std::string& user)>;
  using AcceptHook = std::function<void(Session&, const AcceptEvent&)>;

  /// Options from the runtime's config.
  explicit Session(std::shared_ptr<Runtime> runtime);
  Session(std::shared_ptr<Runtime> runtime, SessionOptions options);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// One request line -> one answer line (no trailing newline). Empty (blank) lines give an empty
  /// string: no answer. Never throws. Lines longer than input.max_line_bytes or nested deeper
  /// than input.max_json_depth are refused before they are parsed.
  std::string handle_line(std::string_view line);
  /// The answer to a line a front end did not keep because it was longer than
  /// input.max_line_bytes (`bytes` read so far, at least the limit + 1).
  std::string line_too_long(std::uint64_t bytes) const;
  /// The deadline of the request being handled (session.deadline_ms after it arrived).
  std::chrono::steady_clock::time_point deadline() const { return deadline_; }
  /// Throws sdk::Error(deadline_exceeded) naming `stage` when the deadline has passed.
  void check_deadline(const char* stage) const;
  /// Throws sdk::Error(input_too_long) when `text` has more than input.max_chars code points.
  void check_length(std::string_view text) const;
  /// The same for an already parsed request. Never throws.
  Json handle(const Json& request);

  /// Installs or replaces an op.
  void set_op(const std::string& name, OpHandler handler);
  /// The current handler of an op (to wrap it), or null.
  const OpHandler* find_op(const std::string& name) const;
  std::vector<std::string> op_names() const;

  /// Per-user rule visibility (sharing modes). Default: every rule is visible.
  void set_visibility(VisibilityHook hook) { visibility_ = std::move(hook); }
  /// Called during an accept after the scorer has learned and the use counters were counted,
  /// before the world changes; when it throws, the accept is undone (scorer state, counters),
  /// the world and the last query stay, and the error is the answer (a retry applies it once).
  void set_on_accept(AcceptHook hook) { on_accept_ = std::move(hook); }
  /// Adds an observer told about every accepted plan, after the accept hook.
  void add_plan_observer(std::shared_ptr<AcceptedPlanObserver> observer) {
    plan_observers_.push_back(std::move(observer));
  }

  Runtime& runtime() { return *runtime_; }
  const Runtime& runtime() const { return *runtime_; }
  const SessionOptions& options() const { return options_; }
  const Executor& executor() const { return executor_; }

  const sdk::WorldState& world() const { return world_; }
  /// Replaces the current world (and forgets the last query, whose plans no longer apply).
  void set_world(sdk::WorldState world);
  const std::string& user() const { return user_; }
  void set_user(std::string name) { user_ = std::move(name); }
  /// Null before the first query, after an accept and after a world change.
  const LastQuery* last_query() const { return last_query_.get(); }
  /// The rule filter for the current user (null when every rule is visible).
  std::function<bool(const sdk::Rule&)> visible_rules() const;

  /// The world object of a state, as the world plugin writes it.
  Json world_json(const sdk::WorldState& state) const;
  /// The world of a state for an answer payload. While handle_line runs this is a placeholder
  /// that handle_line replaces by the world's text, so worlds skip the JSON tree entirely;
  /// otherwise it is world_json(state).
  Json answer_world(const sdk::WorldState& state);
  /// The protocol version the client asked for with `hello` (docs/protocol.md § "Protocol versions"); 1 by default.
  int protocol() const { return protocol_; }
  /// A world that changed in a protocol-1 answer is the full object (answer_world); in protocol 2
  /// it is only `{"items", "robot"}`, and add_world_version() must be called for the answer.
  Json answer_changed_world(const sdk::WorldState& state);
  /// Protocol 2: adds "world_version" (the id of the state's geometry and rooms) to `payload`,
  /// and "geometry" (the world object without items and robot) when this client has not been
  /// sent that version yet or `always` is set. Protocol 1: does nothing.
  void add_world_version(Json& payload, const sdk::WorldState& state, bool always = false);

 private:
  struct CachedWorld {
    sdk::WorldState state;
    std::string text;
  };
  /// The full text for a state; the last few are cached (candidates often end in the same
  /// world, and the current world is written again and again).
  const std::string& world_text(const sdk::WorldState& state);
  /// JSON text for an answer payload: a placeholder in line mode, else parsed.
  Json raw_json(std::string text);
  std::string splice_worlds(std::string answer) const;
  /// A trace for an answer payload: like answer_world, a placeholder for its text in line mode.
  Json answer_trace(const std::vector<sdk::TraceStep>& trace, int dims);

  void install_default_ops();
  Json op_hello(const Json& request);
  Json op_world(const Json& request);
  sdk::WorldState load_requested_world(const std::string& text, const std::string& base);
  Json op_user(const Json& request);
  Json op_state(const Json& request);
  Json op_query(const Json& request);
  Json op_accept(const Json& request);
  void notify_plan_observers(const LastQuery& q, const ShownCandidate& sc,
                             const sdk::Outcome& outcome);

  std::shared_ptr<Runtime> runtime_;
  SessionOptions options_;
  Executor executor_;
  sdk::WorldState world_;
  std::string user_ = "anonymous";
  std::unique_ptr<LastQuery> last_query_;
  std::map<std::string, OpHandler, std::less<>> ops_;
  VisibilityHook visibility_;
  AcceptHook on_accept_;
  std::vector<std::shared_ptr<AcceptedPlanObserver>> plan_observers_;
  std::uint64_t accepted_plans_ = 0;
  std::vector<CachedWorld> world_cache_;  // most recent first
  std::unique_ptr<WorldTexts> texts_;     // world texts by version (world_texts.hpp)
  struct LoadedWorld {                    // a world op's input and what it loaded
    std::string base, text;
    sdk::WorldState state;
  };
  std::vector<LoadedWorld> loaded_;  // the last few, most recent first
  int protocol_ = 1;
  std::vector<std::uint64_t> sent_versions_;  // protocol 2: versions whose geometry was sent
  std::string_view line_;                     // the request line being handled (handle_line)
  bool line_mode_ = false;                    // inside handle_line: answer_world gives placeholders
  std::vector<std::string> spliced_;          // world and trace texts of the answer being built
  std::string marker_;                        // placeholder prefix, unique per session
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
};

}  // namespace flipper::kernel
