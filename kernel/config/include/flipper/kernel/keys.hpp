#pragma once
/// @file keys.hpp
/// Typed handles of the kernel config keys whose values code reads into option structs. Each is
/// one declaration: path, default, range and description. The kernel schema (keys.cpp, an
/// sdk::ParamSchema — the engine plugins' params use) is built from these and from the other
/// keys declared there, the option structs (ExecLimits, InputLimits, SessionOptions, ...) take
/// their initial values from them and fill themselves with Config::get(handle), so a default
/// lives in one place; configs/default.yaml restates none, and `flipper config explain` and the
/// README's key table print the schema.

#include <cstdint>
#include <string_view>

namespace flipper::kernel::keys {

/// An integer key: dotted path, default, inclusive range, description.
struct Int {
  std::string_view path;
  std::int64_t def;
  std::int64_t min;
  std::int64_t max;
  std::string_view doc;
};

/// A boolean key.
struct Bool {
  std::string_view path;
  bool def;
  std::string_view doc;
};

/// A string key (no fixed choices).
struct Text {
  std::string_view path;
  std::string_view def;
  std::string_view doc;
};

inline constexpr Int kSessionK{"session.k", 3, 1, 1000, "candidates shown per query"};
// Time limits (docs/planners.md §2): a CPU-time budget on the request thread decides, the same on
// a quiet or a busy machine; the wall-clock deadline is a far backstop that only ends runaways
// (work that uses no CPU on the request thread: a wait, a sleep). It is far because a starved
// thread is no runaway: at nice 19 beside two busy loops on a loaded 2-core machine a thread got
// 0.2 % of a core (measured), so 10 minutes of wall time may be 1.2 s of CPU. Either limit gives
// deadline_exceeded with `stopped` naming it.
inline constexpr Int kCpuBudgetMs{"session.cpu_budget_ms", 5000, 1, 86400000,
                                  "CPU time of one request on its thread, end to end (parsing "
                                  "included): then deadline_exceeded, stopped: cpu_budget"};
inline constexpr Int kDeadlineMs{"session.deadline_ms", 600000, 1, 86400000,
                                 "wall-clock backstop of one request, end to end, against hangs "
                                 "(not load): then deadline_exceeded, stopped: wall_backstop"};
inline constexpr Int kActionBudget{"execution.action_budget", 100000, 1, 1000000000000,
                                   "primitive actions one program may take (work: then "
                                   "budget_exceeded)"};
inline constexpr Int kStepBudget{"execution.step_budget", 1000000, 1, 1000000000000,
                                 "statements one program may execute, loop iterations and "
                                 "trial runs included (work: then budget_exceeded)"};
inline constexpr Int kExecCpuBudgetMs{"execution.cpu_budget_ms", 2000, 1, 86400000,
                                      "CPU time of one execution on the request thread: then "
                                      "deadline_exceeded, stopped: cpu_budget (never a different "
                                      "plan)"};
inline constexpr Int kExecDeadlineMs{"execution.deadline_ms", 300000, 1, 86400000,
                                     "wall-clock backstop of one execution, against hangs (not "
                                     "load): then deadline_exceeded, stopped: wall_backstop"};
inline constexpr Int kWhileLimit{"execution.while_limit", 20, 0, 1000000,
                                 "iterations of one `while`"};
inline constexpr Int kMaxChars{"input.max_chars", 2000, 1, 100000000,
                               "code points of an utterance"};
inline constexpr Int kMaxSemicolons{"input.max_semicolons", 30, 1, 1000000,
                                    "statements of an utterance"};
inline constexpr Int kMaxLineBytes{"input.max_line_bytes", 1048576, 64, 1073741824,
                                   "one request line"};
inline constexpr Int kMaxJsonDepth{"input.max_json_depth", 64, 2, 10000, "nesting of a request"};
inline constexpr Int kMaxTokens{"input.max_tokens", 400, 1, 65534,
                                "tokens of a query, a define head, each body line"};
inline constexpr Int kMaxBodyLines{"input.max_body_lines", 100, 1, 100000,
                                   "lines of a definition's body"};
inline constexpr Int kMaxFileBytes{"input.max_file_bytes", 67108864, 1, 1099511627776,
                                   "world, grammar and preload files"};
// docs/plugins-untrusted.md §6: a planner's plan and tour calls each in a child process, so a
// crash or hang costs one answer; `auto` is `process` in the servers (serve, dds), where a crash
// would lose other users' work, and `in_process` elsewhere.
inline constexpr Text kPluginIsolation{"plugins.isolation", "auto",
                                       "where a planner's plan and tour calls run: in_process, "
                                       "process (a child process each: a crash costs one answer, "
                                       "plugin_crashed), auto (process in serve and dds)"};
inline constexpr Int kMaxWorldCells{"world.max_cells", 4194304, 1, 268435456, "cells of a world"};
inline constexpr Int kBusyTimeoutMs{"lexicon.busy_timeout_ms", 10000, 1, 600000,
                                    "longest wait for other writers, then lexicon_busy"};
inline constexpr Int kSnapshotMinRules{
    "lexicon.snapshot_min_rules", 512, 0, 1000000000,
    "keep a rule snapshot for fast start-up once the store holds this many live rules "
    "(docs/naturalization.md §5); 0: never"};
inline constexpr Bool kAlignment{"induction.alignment", true,
                                 "induce rules by aligning head and body"};
inline constexpr Bool kGeneralize{"induction.generalize", true,
                                  "generalize definitions by rewriting"};
inline constexpr Int kPerturbedChecks{"induction.perturbed_checks", 0, 0, 1000,
                                      "perturbed worlds a generalization is checked on"};

inline constexpr Text kServeHost{"serve.host", "127.0.0.1", "address to listen on"};
inline constexpr Int kServePort{"serve.port", 8410, 0, 65535, "port (0: any free port, printed)"};
inline constexpr Int kServeThreads{"serve.threads", 4, 1, 256, "worker threads running requests"};
inline constexpr Int kServeMaxRequestBytes{"serve.max_request_bytes", 65536, 256, 67108864,
                                           "larger bodies: 413"};
inline constexpr Int kServeRatePerSecond{"serve.rate_per_second", 100, 1, 1000000,
                                         "requests per session per second"};
inline constexpr Int kServeRateBurst{"serve.rate_burst", 200, 1, 1000000, "burst per session"};
inline constexpr Int kServeMaxSessions{"serve.max_sessions", 1000, 1, 1000000, "open sessions"};
inline constexpr Int kServeSessionIdleS{"serve.session_idle_s", 3600, 1, 31536000,
                                        "idle seconds before a session may be evicted"};
inline constexpr Bool kServeSempre{"serve.sempre", false,
                                   "also answer the 2018 server's API at GET /sempre, to any web "
                                   "page (docs/sempre.md)"};
inline constexpr Bool kServeGuests{"serve.guests", true,
                                   "guests may use the server without an account"};
inline constexpr Int kServeLoginDays{"serve.login_days", 30, 1, 3650,
                                     "days a login (its cookie) lasts"};
inline constexpr Int kServeRequestTimeoutMs{"serve.request_timeout_ms", 10000, 100, 600000,
                                            "reading one request, headers and body"};
inline constexpr Int kServeIdleTimeoutMs{"serve.idle_timeout_ms", 5000, 100, 600000,
                                         "an idle keep-alive connection"};
inline constexpr Int kServeMaxConnections{"serve.max_connections", 1024, 1, 1000000,
                                          "open connections"};
inline constexpr Int kServeMaxConnectionsPerAddress{"serve.max_connections_per_address", 64, 1,
                                                    1000000, "open connections per client address"};
inline constexpr Int kServeSessionsPerAddress{"serve.sessions_per_address", 32, 1, 1000000,
                                              "open sessions per client address"};
inline constexpr Int kServeNewSessionsPerMinute{"serve.new_sessions_per_minute", 60, 1, 1000000,
                                                "new sessions per client address per minute"};
inline constexpr Int kServeMemoryBudgetMb{"serve.memory_budget_mb", 1024, 1, 1048576,
                                          "memory for all sessions' state (worlds)"};
inline constexpr Int kServeEvictAfterS{"serve.evict_after_s", 120, 0, 31536000,
                                       "idle seconds before the memory budget may evict"};
inline constexpr Int kServeCpuMsPerS{"serve.cpu_ms_per_s", 500, 1, 1000000,
                                     "CPU time per session per second"};
inline constexpr Int kServeCpuBurstMs{"serve.cpu_burst_ms", 5000, 1, 100000000,
                                      "CPU time a session may bank"};
inline constexpr Int kServeKernels{"serve.kernels", 0, 0, 64,
                                   "kernels answering at once (0: the cores + 1)"};

}  // namespace flipper::kernel::keys
