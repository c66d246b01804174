#pragma once
/// @file answer_check.hpp
/// The one check of what plugins answer, shared by the kernel (which applies it where every
/// planner and parser answer enters it, kernel/plugin_checks.hpp), `bench planners` and the
/// conformance kit, so that none of them can accept an answer another refuses
/// (docs/plugins-untrusted.md). Each function says what is wrong, first thing found, in words a
/// plugin author can act on ("step 3 enters wall [9,3]"), or nothing.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

// Declared only (flipper/sdk/planner.hpp, parser.hpp and scorer.hpp define them): this header may
// come first (kernel/plugin_checks.hpp includes it for these declarations), and ast.hpp included
// after geometry.hpp trips GCC's -Wshadow on Sort::Area.
struct Cell;
class Geometry;
class Planner;
struct PathRequest;
struct PathResult;
struct StopCondition;
struct TourResult;
class Parser;
struct ParseRequest;
struct ParseResult;
struct Candidate;
class Scorer;
struct ScoreContext;
struct WeightChange;

namespace codes {
/// A planner's path or tour that is not an answer to the request.
inline constexpr const char* kInvalidPlan = "invalid_plan";
/// A parser's candidate that is not a well-formed program over the utterance.
inline constexpr const char* kInvalidCandidate = "invalid_candidate";
/// A candidate's or derivation's score that is not a finite number.
inline constexpr const char* kInvalidScore = "invalid_score";
/// A scorer's weights read from a saved state (StateWeights) that are not finite numbers, or
/// more of them than the state has bytes.
inline constexpr const char* kInvalidWeights = "invalid_weights";
}  // namespace codes

/// What is wrong with an answer: its code (codes::kInvalid*) and what it broke, in words.
struct Violation {
  const char* code = nullptr;
  std::string what;
};

/// A found path that is not a path from `request.start` to a goal of `request` on `geometry`:
/// a step outside the world, a step that is not one of geometry.neighbour_offsets(), a step into
/// a blocked cell or the request's avoid area (the start is exempt), a path that does not end at
/// the target it reports, a target that is not a free goal cell. Steps count from 1. Answers
/// other than `found` are not acted on and have nothing to check.
FLIPPER_SDK_API std::optional<std::string> path_violation(const Geometry& geometry,
                                                          const PathRequest& request,
                                                          const PathResult& result);

/// A found tour whose order is not a permutation of 0..points-1.
FLIPPER_SDK_API std::optional<std::string> tour_violation(std::size_t points,
                                                          const TourResult& result);

/// A candidate that is not a well-formed, hole-free statement (as sdk::make builds them) with
/// its loop variables bound (core-language §3.7); a derivation without a rule or whose span is
/// not within its parent's and the utterance's tokens (a candidate's, with whole_span, the whole
/// utterance); a score (candidate or derivation) that is not finite. The chart's derivations
/// (want_chart) are checked the same way. Code: kInvalidCandidate or kInvalidScore.
FLIPPER_SDK_API std::optional<Violation> parse_violation(const ParseRequest& request,
                                                         const ParseResult& result);

/// Weights a scorer read from a saved state of `state_bytes` bytes (StateWeights::state_weights)
/// that break its contract: a weight or aux that is not finite, or more weights than the state
/// has bytes. Code: kInvalidWeights.
FLIPPER_SDK_API std::optional<std::string> state_weights_violation(
    std::size_t state_bytes, const std::vector<WeightChange>& weights);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
