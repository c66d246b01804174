#pragma once
/// @file answer_wire.hpp
/// Plugin answers as bytes and back, for a host that runs plugin calls in a child process
/// (the kernel's plugins.isolation, docs/plugins-untrusted.md §6): a planner's path and tour, a
/// parser's result, a scorer's learnt weights. Every field crosses as it is (a program node's hash
/// and size too) and what is shared stays shared, so the decoded answer is the child's, byte for
/// byte. The bytes come from the untrusted plugin's process: decoding checks every length, index
/// and enumeration value and gives nothing for bytes it cannot read whole; what a readable answer
/// holds is then judged by answer_check.hpp, as for an answer made in process.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace host {

FLIPPER_SDK_API std::string to_bytes(const PathResult& result);
FLIPPER_SDK_API std::string to_bytes(const TourResult& result);
/// An error a call in a child process threw, for its parent to throw again: its stop cause
/// (sdk::StopCause's value, 0: none), code and message.
struct CallFailure {
  std::uint64_t cause = 0;
  std::string code;
  std::string message;
};
FLIPPER_SDK_API std::string to_bytes(const CallFailure& failure);
FLIPPER_SDK_API std::optional<CallFailure> call_failure_of(std::string_view bytes);

/// Program nodes, rules and derivations as tables, each entry after the ones it points to.
FLIPPER_SDK_API std::string to_bytes(const ParseResult& result);
/// A scorer's learnt weights as values (sdk::WeightValues::pending_values).
FLIPPER_SDK_API std::string to_bytes(const std::vector<WeightChange>& values);

/// The answer `bytes` hold, or nothing when they are not one whole answer of that type.
FLIPPER_SDK_API std::optional<PathResult> path_result_of(std::string_view bytes);
FLIPPER_SDK_API std::optional<TourResult> tour_result_of(std::string_view bytes);
FLIPPER_SDK_API std::optional<ParseResult> parse_result_of(std::string_view bytes);
/// Nothing also when a weight or its aux is not finite.
FLIPPER_SDK_API std::optional<std::vector<WeightChange>> weight_values_of(std::string_view bytes);

/// A scorer's learn in a child process (docs/plugins-untrusted.md §6). Whether it can: a scorer
/// with sdk::WeightValues, or one without sdk::IncrementalScorer (its whole state crosses); an
/// incremental scorer without values cannot (its pending changes would be lost).
FLIPPER_SDK_API bool learns_apart(const Scorer& scorer);
/// In the child, after learn(): the learnt weights as values, or the whole saved state.
FLIPPER_SDK_API std::string learnt_bytes(const Scorer& scorer);
/// In the parent: sets the values (WeightValues::set_values, pending as after learn()) or loads
/// the state; false, having changed nothing, when `bytes` are not whole finite values.
FLIPPER_SDK_API bool apply_learnt(Scorer& scorer, std::string_view bytes);

}  // namespace host
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
