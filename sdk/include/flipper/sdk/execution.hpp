#pragma once
/// @file execution.hpp
/// The result of running a program (core-language §5): the trace of what the robot did, the
/// warnings, and the final world. The kernel owns the executor; plugins that need to run
/// programs (the rewriter checks equivalence, for instance) get an `ExecutionService`.

#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/stop.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// One trace step: a move into a cell, or an item picked/dropped at a cell.
struct TraceStep {
  /// Values cross the plugin boundary: pinned in sdk/src/abi_pins.cpp; never renumber, only append.
  enum class Act { move = 0, pick = 1, drop = 2 };
  Act act = Act::move;
  Cell cell;      ///< `to` for moves, `at` for pick/drop
  ItemInfo item;  ///< pick/drop only
  friend bool operator==(const TraceStep&, const TraceStep&) = default;
};

/// The outcome of one execution.
struct Outcome {
  WorldState world;  ///< the final world (the start world if `error`)
  std::vector<TraceStep> trace;
  std::vector<std::string> warnings;  ///< one per failed primitive (+ rolled-back strict blocks)
  bool realizable = true;             ///< every primitive executed for real succeeded
  std::optional<std::string> error;   ///< execution error (unknown room, budget exceeded...)
  std::optional<std::string> error_code;  ///< e.g. "budget_exceeded", "execution_error"
  StopCause stopped = StopCause::none;    ///< with deadline_exceeded: the limit that fired
  std::uint64_t actions = 0;              ///< primitive actions executed (trials included)
};

/// Runs programs with the kernel's executor and the session's planner. Thread-compatible.
class FLIPPER_SDK_API ExecutionService {
 public:
  virtual ~ExecutionService();
  /// Runs `program` leniently on a copy of `world`.
  virtual Outcome run(const Program& program, const WorldState& world) const = 0;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
