#pragma once
/// @file accept_diff.hpp
/// Why our execution of an accepted program ends in another world than the one the study's
/// client sent next. Shared by the replay (apps/replay: accepts.csv, metrics.json, report.md)
/// and the executor's corpus differential (tests/language/exec/test_corpus_accepts.cpp), so both
/// count the same classes.
///
/// The classes, tried in this order (first match wins):
/// - budget_exceeded / execution_error: our execution failed (§9 / §4.2 [decision]);
/// - agree: robot cell, held items and floor items (multisets) are equal;
/// - start_differs: we did not start from the logged world before (a replay fault);
/// - reset: the next world cannot come from a command (other layout, items appear or vanish,
///   or the study's start world again);
/// - no_change_logged: the next world equals the world before (the client did not apply it);
/// - client_state: our trace equals the original's own run of that candidate (its `result`),
///   so the logged next world reflects client state, not the program;
/// - failed_movement: a move/visit failed and left the robot in place (§6);
/// - item_choice / nearest_cell / loop_order (tie rules and tour T, §8 [decision]): proven by
///   re-executing the program with another tie choice — an eligible item the log shows moved
///   instead of the first, an equally near cell the log shows visited instead of the smallest, a
///   loop order that ends at the logged robot cell — and getting the logged next world exactly
///   (src/tie_proofs.hpp);
/// - visit_collection: kept as an id for old outputs; no proof reaches it any more;
/// - unexplained: none of the above proves it; unreadable: the original's text does not read.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::corpus {

/// Robot cell, carried items and floor items as sorted multisets ("colour shape",
/// "x,y colour shape"): item ids and list order do not take part in comparisons.
struct WorldSnapshot {
  int x = 0, y = 0;
  std::vector<std::string> held, floor;
  bool operator==(const WorldSnapshot&) const = default;
};
/// From a protocol world object or a worlds.jsonl record.
WorldSnapshot snapshot(const nlohmann::json& world);
WorldSnapshot snapshot(const sdk::WorldState& world);

/// One comparable step: "m x y", "p x y colour shape" or "d x y colour shape".
using Steps = std::vector<std::string>;
Steps our_steps(const std::vector<sdk::TraceStep>& trace);
/// The original's `result.path` from `robot` (§5): start entries, zero-length destinations and
/// entries with possible = false are dropped.
Steps original_steps(const nlohmann::json& path, sdk::Cell robot);

/// The corpus's study start world: a client that sends it again after a command was reset.
inline constexpr std::string_view kStudyStartWorld = "wdd05b0e5ff41";

enum class AcceptClass {
  agree,
  start_differs,
  budget_exceeded,
  execution_error,
  reset,
  no_change_logged,
  client_state,
  failed_movement,
  loop_order,
  visit_collection,
  item_choice,
  nearest_cell,
  unexplained,
  unreadable,
};

/// Stable short id (CSV/JSON), e.g. "loop_order".
const char* class_id(AcceptClass c);
/// One-line explanation with the spec reference, e.g. "loop order: tour T (§8 [decision])".
const char* class_label(AcceptClass c);
/// unexplained, unreadable and start_differs: differences nothing in the spec accounts for.
bool is_unexplained(AcceptClass c);
/// Every class in declaration order (for tables).
const std::vector<AcceptClass>& all_classes();
/// The class with that class_id, if any.
std::optional<AcceptClass> class_from_id(std::string_view id);

/// One executed accept.
struct AcceptCase {
  const nlohmann::json& before;  ///< the logged world before (protocol world or record)
  const nlohmann::json& after;   ///< the logged next world
  std::string_view next_world_id;
  const sdk::Program& program;   ///< the accepted program
  const sdk::WorldState& start;  ///< the world we executed it on
  const sdk::Outcome& outcome;   ///< our execution
  /// The original's own run of the candidate (`result.path` in original-answers.jsonl), or null.
  const nlohmann::json* original_path = nullptr;
  /// The planner of our execution; without one no tie-rule proof runs (such differences are
  /// unexplained).
  const sdk::Planner* planner = nullptr;
};

AcceptClass classify_accept(const AcceptCase& c);

}  // namespace flipper::corpus
