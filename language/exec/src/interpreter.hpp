#pragma once
// The interpreter behind Executor: evaluates one program on one world state (core-language §4).
// One Interpreter lives for one execution; trial runs (`possible`, `strict`) reuse it on scratch
// copies of the state with the trace and warning sinks switched off or redirected.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "flipper/language/executor.hpp"
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::language::detail {

/// A collection: a set of areas in first-occurrence order (order matters for §8 ties).
using Collection = std::vector<sdk::Area>;

class Interpreter {
 public:
  Interpreter(const PlannerAccess& planner, const ExecLimits& limits, const sdk::WorldState& start,
              const sdk::StopCondition& request = {});

  /// Runs a statement on `state` (the real run); fills trace and warnings. Returns success.
  /// Throws sdk::Error(execution_error | budget_exceeded | deadline_exceeded).
  bool run(const sdk::Program& program, sdk::WorldState& state, std::vector<sdk::TraceStep>& trace,
           std::vector<std::string>& warnings);
  std::uint64_t actions() const { return actions_; }

 private:
  // Where a run writes; trials switch these off (possible) or redirect warnings (strict).
  struct Sinks {
    std::vector<sdk::TraceStep>* trace = nullptr;
    std::vector<std::string>* warnings = nullptr;
  };

  const PlannerAccess& planner_;
  // Asked once per execution: `optimal` (its paths are shortest, else the executor picks goals),
  // `deterministic` (same request, same answer: tours may be reused), `sampling` ("no path" may
  // mean "none within its budget").
  const sdk::PlannerTraits traits_;
  const sdk::Geometry& geometry_;
  const sdk::RoomMap& rooms_;
  ExecLimits limits_;
  sdk::StopCondition stop_;
  bool request_cpu_binds_ = false;   // less of session.cpu_budget_ms is left than execution's
  bool request_wall_binds_ = false;  // the request's backstop comes before execution.deadline_ms
  std::uint64_t actions_ = 0;
  std::uint64_t steps_ = 0;
  std::vector<sdk::Cell> point_vars_;  // innermost last; popping restores the outer binding (§4.7)
  std::vector<sdk::Area> area_vars_;
  struct LastTour {  // the last `foreach point` order (point_tour)
    bool valid = false;
    sdk::Cell start;
    sdk::Area cells;
    std::vector<std::size_t> order;
  } last_tour_;

  // statements.cpp
  bool exec(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool exec_strict(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool exec_foreach_point(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool exec_foreach_area(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  /// The planner's visiting order of `cells` from `start` (§8), the last one reused when the
  /// planner is deterministic and the request is the same.
  std::vector<std::size_t> point_tour(sdk::Cell start, const sdk::Area& cells);
  bool trial(const sdk::Node& n, const sdk::WorldState& s, std::vector<std::string>* warnings);
  /// Whether a lone pick, drop or move would succeed on `s` (counted like exec() would), or
  /// nullopt for any other statement.
  std::optional<bool> primitive_succeeds(const sdk::Node& n, const sdk::WorldState& s);
  void count_step();  // one statement more (execution.step_budget), the deadline now and then
  void tick();        // the CPU budget and wall backstop: throw deadline_exceeded once one fired

  // actions.cpp: primitives
  bool move(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool visit_point(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool visit_area(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool visit_collection(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool pick(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  bool drop(const sdk::Node& n, sdk::WorldState& s, Sinks& out);
  /// Whether move, pick or drop `n` would succeed on `s`, without running it (budget counted).
  bool action_succeeds(const sdk::Node& n, const sdk::WorldState& s);
  void count_action();
  bool fail(const sdk::Node& n, Sinks& out, const std::string& reason);
  void follow(const sdk::PathResult& path, sdk::WorldState& s, Sinks& out);
  /// "; the planner: <message>" when a failed path is no proof (a sampling planner, or a
  /// planner stopped by its own work budget), so the warning names the budget; else "".
  std::string unproven(const sdk::PathResult& r) const;
  /// A path to the goal nearest by path (§4.4, §8). For planners that are not `optimal` the
  /// kernel picks that goal itself (nearest.hpp) and asks only for a path to it. `distance`,
  /// when given, receives the goal's path distance (what `visit C` compares across areas).
  sdk::PathResult plan(sdk::Cell start, const sdk::Area& goals, const sdk::Area* avoid,
                       std::size_t* distance = nullptr);

  // locations.cpp
  double number(const sdk::Node& n);
  std::int32_t integer(const sdk::Node& n, const char* what);
  sdk::Cell point(const sdk::Node& n, const sdk::WorldState& s);
  sdk::Area area(const sdk::Node& n, const sdk::WorldState& s);
  Collection collection(const sdk::Node& n, const sdk::WorldState& s);
  const sdk::Area& room(const sdk::Node& n);

  // conditions.cpp
  bool condition(const sdk::Node& n, const sdk::WorldState& s);
};

/// Whether an item satisfies an item description (Item node: `item` or `item F`).
bool matches(const sdk::Node& item, const sdk::ItemInfo& info);
/// "red item", "item", "item {{is red} and {is circle}}" — for warning reasons.
std::string describe(const sdk::Node& item);
/// "[x,y]" or "[x,y,z]".
std::string cell_text(const sdk::Geometry& g, sdk::Cell c);

}  // namespace flipper::language::detail
