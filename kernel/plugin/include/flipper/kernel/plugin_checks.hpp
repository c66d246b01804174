#pragma once
/// @file plugin_checks.hpp
/// Plugin answers checked where they enter the kernel (docs/plugins-untrusted.md). Plugins are
/// untrusted: every planner path and tour and every parse the kernel acts on comes through these
/// calls (the executor behind `run`, `session`, `serve`, `dds` and `replay`; a query's and a
/// definition's parse; `bench planners`), so no front end can act on an answer another refuses.
/// Each makes the plugin call through its PluginRef (a throwing plugin is plugin_error there),
/// then applies the SDK's one check of the answer (flipper/sdk/answer_check.hpp) and throws
/// sdk::Error(invalid_plan | invalid_candidate | invalid_score | invalid_weights, "plugin 'NAME'
/// (FILE): WHAT") when the answer breaks its contract: nothing of it is acted on.

#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/answer_check.hpp"  // declares the SDK types used here
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::kernel {

/// Throws sdk::Error(code, "plugin 'NAME' (FILE): WHAT").
[[noreturn]] void throw_invalid_output(const PluginId& plugin, const char* code,
                                       const std::string& what);

/// planner.plan(geometry, request, stop), its path checked (invalid_plan).
sdk::PathResult checked_plan(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, const sdk::PathRequest& request,
                             const sdk::StopCondition& stop);

/// planner.tour(geometry, start, points, stop), its order checked (invalid_plan).
sdk::TourResult checked_tour(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, sdk::Cell start,
                             const std::vector<sdk::Cell>& points, const sdk::StopCondition& stop);

/// parser.parse(request), its candidates checked (invalid_candidate, invalid_score).
sdk::ParseResult checked_parse(const PluginRef<const sdk::Parser>& parser,
                               const sdk::ParseRequest& request);

/// What one parse of a series gave: its result, or the error it ended with.
struct ParseOutcome {
  sdk::ParseResult result;
  std::exception_ptr error;  ///< set: the parse threw, or its answer broke the contract
};

/// checked_parse of each request in order, as calls one after another would make them, but in
/// one child process when the parser is isolated (one fork for a definition's head and body
/// lines, or for its conflict probes: docs/plugins-untrusted.md §6). The outcomes end with the
/// first parse that fails: the ones after it are not made. Isolated, every parse is bounded by
/// the budget `stop` has left (the child's, shared by the series, as in process where each
/// request's own stop is used: callers give them all `stop`). The child sends each answer as
/// it is made, so a child that dies midway leaves the parses it answered their results and the
/// next parse the crash (plugin_crashed); bytes that are not a series are plugin_crashed ("its
/// process sent a malformed answer") for the parse after the last whole answer.
std::vector<ParseOutcome> checked_parses(const PluginRef<const sdk::Parser>& parser,
                                         const std::vector<sdk::ParseRequest>& requests,
                                         const sdk::StopCondition& stop);

/// The scorer's reading of a state it saved (sdk::StateWeights, which `reader` is: the scorer's
/// own object), its weights checked (invalid_weights); nullopt when it does not read `state`.
std::optional<std::vector<sdk::WeightChange>> checked_state_weights(
    const PluginRef<sdk::Scorer>& scorer, const sdk::StateWeights& reader,
    const std::string& state);

/// scorer.learn(candidates, accepted, ctx), in a child process when the ref says so.
void checked_learn(const PluginRef<sdk::Scorer>& scorer,
                   const std::vector<sdk::Candidate>& candidates, std::size_t accepted,
                   const sdk::ScoreContext& ctx, const sdk::StopCondition& stop);

}  // namespace flipper::kernel
