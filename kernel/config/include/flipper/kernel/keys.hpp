#pragma once
/// @file keys.hpp
/// The kernel's own config keys (docs/config.md "Who declares a key"): the plugin sections, the
/// world and grammar files, input and session limits, plugin_paths (`execution` is the core
/// language's: flipper/language/keys.hpp, in the kernel's fragment). Each is one typed
/// handle of the SDK (flipper/sdk/config_handles.hpp): path, default, range and description. The
/// kernel's schema fragment (keys.cpp) is built from them, the option structs (ExecLimits,
/// InputLimits, SessionOptions, ...) take their initial values from them and fill themselves with
/// Config::get(handle), so a default lives in one place. The layers above declare their own keys
/// the same way (naturalization: lexicon.*, induction.*; studio: serve.*; dds: dds.*, publish.*),
/// and the host composes the fragments before it loads a config (Config::install_schema).

#include <cstdint>
#include <string_view>

#include "flipper/sdk/config_handles.hpp"

namespace flipper::kernel::keys {

using Int = sdk::param::Int<std::int64_t>;
using Bool = sdk::param::Bool;
using Text = sdk::param::Text;
using Path = sdk::param::Path;
template <std::size_t N>
using TextList = sdk::param::TextList<N>;

inline constexpr Path kWorldFile{"world.file", "worlds/study2018.json", "the default world"};
inline constexpr sdk::param::Double kWorldResolution{"world.resolution", 1.0, 0.001, 1000,
                                                     "metres per cell (plans over DDS)"};
inline constexpr sdk::param::DoubleList<3> kWorldOrigin{
    "world.origin", {0, 0, 0}, "metres of cell (0, 0, 0) (plans over DDS)"};
inline constexpr Path kGrammarFile{"grammar.file", "grammars/core.grammar", "the core grammar"};
inline constexpr TextList<9> kGrammarColors{
    "grammar.colors",
    {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
    "colour words"};
inline constexpr TextList<3> kGrammarShapes{
    "grammar.shapes", {"triangle", "circle", "square"}, "shape words"};
inline constexpr TextList<0> kGrammarDirections{
    "grammar.directions",
    {},
    "a subset of the world plugin's direction words (empty: all of them)"};
inline constexpr sdk::param::PathList<0> kPluginPaths{
    "plugin_paths", {}, "more directories to find plugins in"};

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
// docs/plugins-untrusted.md §6: a planner's plan and tour calls and a parser's parse (with the
// scorer calls it makes) each in a child process, so a crash or hang costs one answer; `auto` is
// `process` in the servers (serve, dds), where a crash would lose other users' work, and
// `in_process` elsewhere.
/// plugins.isolation, in the order of its names (`automatic` is the name "auto").
enum class PluginIsolation { automatic, in_process, process };
inline constexpr sdk::param::Choice<PluginIsolation, 3> kPluginIsolation{
    "plugins.isolation",
    PluginIsolation::automatic,
    {"auto", "in_process", "process"},
    "where a planner's plan and tour and a parser's parse (its scorer calls with it) run: "
    "in_process, process (a child process each: a crash costs one answer, plugin_crashed), auto "
    "(process in serve and dds)"};
inline constexpr Int kMaxWorldCells{"world.max_cells", 4194304, 1, 268435456, "cells of a world"};
}  // namespace flipper::kernel::keys
