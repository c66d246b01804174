// Composite statements (core-language §4.5), trials for `possible`/`strict`, loop variables
// (§4.7) and the loop orders of §8.
#include <algorithm>
#include <numeric>
#include <optional>
#include <string>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "interpreter.hpp"

namespace flipper::language::detail {

using sdk::Area;
using sdk::Cell;
using sdk::Kind;
using sdk::Node;
using sdk::WorldState;

Interpreter::Interpreter(const PlannerAccess& planner, const ExecLimits& limits,
                         const WorldState& start, const sdk::StopCondition& request)
    : planner_(planner),
      traits_(planner.traits()),
      geometry_(*start.geometry),
      rooms_(*start.rooms),
      limits_(limits) {
  // docs/planners.md §2: the CPU budget counts this thread's CPU time (plugins run on it); the
  // request's budget, on its own clock, binds when less of it is left than execution's.
  stop_.cancel = request.cancel;
  stop_.cpu_clock = sdk::this_thread_cpu_clock();
  const auto wall_now = std::chrono::steady_clock::now();
  // Remembered on this thread: the polls after it read the clock only near a budget's end.
  const auto cpu_now = sdk::read_cpu_clock(stop_.cpu_clock, wall_now);
  const std::chrono::nanoseconds own = limits.cpu_budget;
  // The request's budget is usually on this same clock (the request thread's): one reading serves
  // both (a thread CPU clock read is a system call, ~1.5 µs on a VM; one per executed candidate).
  std::chrono::nanoseconds left = std::chrono::nanoseconds::max();
  if (request.cpu_deadline == std::chrono::nanoseconds::max())
    left = request.cpu_deadline;
  else if (request.cpu_clock == stop_.cpu_clock)
    left = cpu_now >= request.cpu_deadline ? std::chrono::nanoseconds::zero()
                                           : request.cpu_deadline - cpu_now;
  else
    left = request.cpu_left();
  request_cpu_binds_ = left < own;
  stop_.cpu_deadline = cpu_now + (request_cpu_binds_ ? left : own);
  stop_.deadline = wall_now + limits.deadline;
  if (request.deadline < stop_.deadline) {
    stop_.deadline = request.deadline;
    request_wall_binds_ = true;
  }
}

void Interpreter::count_step() {
  if (++steps_ > limits_.step_budget)
    throw sdk::Error(sdk::codes::kBudgetExceeded, "step budget exceeded: more than " +
                                                      std::to_string(limits_.step_budget) +
                                                      " statements (execution.step_budget)");
  if ((steps_ & 1023u) == 0) tick();
}

void Interpreter::tick() {
  switch (stop_.cause()) {
    case sdk::StopCause::none:
      return;
    case sdk::StopCause::cancelled:
      throw sdk::StoppedError(sdk::StopCause::cancelled, "deadline exceeded: cancelled");
    case sdk::StopCause::cpu_budget:
      if (request_cpu_binds_)
        throw sdk::StoppedError(sdk::StopCause::cpu_budget,
                                "deadline exceeded: the request used more CPU time than "
                                "session.cpu_budget_ms (stopped: cpu_budget)");
      throw sdk::StoppedError(sdk::StopCause::cpu_budget,
                              "deadline exceeded: the execution used more CPU time than "
                              "execution.cpu_budget_ms = " +
                                  std::to_string(limits_.cpu_budget.count()) +
                                  " ms (stopped: cpu_budget)");
    case sdk::StopCause::wall_backstop:
      if (request_wall_binds_)
        throw sdk::StoppedError(sdk::StopCause::wall_backstop,
                                "deadline exceeded: the request took longer than "
                                "session.deadline_ms, the wall-clock backstop (stopped: "
                                "wall_backstop)");
      throw sdk::StoppedError(sdk::StopCause::wall_backstop,
                              "deadline exceeded: the execution took longer than "
                              "execution.deadline_ms = " +
                                  std::to_string(limits_.deadline.count()) +
                                  " ms, the wall-clock backstop (stopped: wall_backstop)");
  }
}

bool Interpreter::run(const sdk::Program& program, WorldState& state,
                      std::vector<sdk::TraceStep>& trace, std::vector<std::string>& warnings) {
  Sinks out{&trace, &warnings};
  return exec(*program, state, out);
}

bool Interpreter::trial(const Node& n, const WorldState& s, std::vector<std::string>* warnings) {
  // `possible` of a lone pick, drop or move: decided on the state itself, without the copy of
  // every item (`if possible {drop item}` inside `foreach point in world` runs per cell).
  if (warnings == nullptr)
    if (const auto quick = primitive_succeeds(n, s)) return *quick;
  WorldState scratch = s;
  Sinks out{nullptr, warnings};
  return exec(n, scratch, out);
}

bool Interpreter::exec(const Node& n, WorldState& s, Sinks& out) {
  // Loops without primitive actions (`repeat 99 times if ...`) count too, and see the clock.
  count_step();
  switch (n.kind) {
    case Kind::Seq: {
      bool ok = true;
      for (const auto& k : n.kids) ok = exec(*k, s, out) && ok;
      return ok;
    }
    case Kind::Strict:
      return exec_strict(n, s, out);
    case Kind::Move:
      return move(n, s, out);
    case Kind::VisitPoint:
      return visit_point(n, s, out);
    case Kind::VisitArea:
      return visit_area(n, s, out);
    case Kind::VisitCollection:
      return visit_collection(n, s, out);
    case Kind::Pick:
      return pick(n, s, out);
    case Kind::Drop:
      return drop(n, s, out);
    case Kind::ForeachPoint:
      return exec_foreach_point(n, s, out);
    case Kind::ForeachArea:
      return exec_foreach_area(n, s, out);
    case Kind::Repeat: {
      const std::int32_t times = integer(*n.kids[0], "repeat count");
      bool ok = true;
      for (std::int32_t i = 0; i < times; ++i) ok = exec(*n.kids[1], s, out) && ok;
      return ok;
    }
    case Kind::If:
      return condition(*n.kids[0], s) ? exec(*n.kids[1], s, out) : true;
    case Kind::While: {
      bool ok = true;
      for (int i = 0; i < limits_.while_limit && condition(*n.kids[0], s); ++i)
        ok = exec(*n.kids[1], s, out) && ok;
      return ok;
    }
    case Kind::Hole:
      throw sdk::Error(sdk::codes::kExecution, "cannot execute a template with holes");
    default:
      throw sdk::Error(sdk::codes::kExecution,
                       std::string("not a statement: ") + sdk::kind_name(n.kind));
  }
}

std::optional<bool> Interpreter::primitive_succeeds(const Node& n, const WorldState& s) {
  const Node* a = &n;
  if (a->kind == Kind::Seq && a->kids.size() == 1) a = a->kids[0].get();  // `{drop item}`
  if (a->kind != Kind::Pick && a->kind != Kind::Drop && a->kind != Kind::Move) return std::nullopt;
  // The same budget steps as exec() (once per statement) and the action (actions.cpp).
  for (const Node* k = &n;; k = k->kids[0].get()) {
    count_step();
    if (k == a) break;
  }
  return action_succeeds(*a, s);
}

bool Interpreter::exec_strict(const Node& n, WorldState& s, Sinks& out) {
  std::vector<std::string> trial_warnings;
  if (trial(*n.kids[0], s, out.warnings ? &trial_warnings : nullptr))
    return exec(*n.kids[0], s, out);
  if (out.warnings != nullptr) {
    for (auto& w : trial_warnings) out.warnings->push_back(std::move(w));
    out.warnings->push_back("Could not complete the action: " +
                            sdk::render(sdk::Program(std::shared_ptr<const Node>(), &n)));
  }
  return false;
}

bool Interpreter::exec_foreach_point(const Node& n, WorldState& s, Sinks& out) {
  const Area cells = area(*n.kids[0], s);
  if (cells.empty()) return true;
  const std::vector<std::size_t> order = point_tour(s.robot, cells);
  bool ok = true;
  point_vars_.push_back(Cell{});
  for (std::size_t i : order) {
    point_vars_.back() = cells[i];
    ok = exec(*n.kids[1], s, out) && ok;
  }
  point_vars_.pop_back();  // restores the enclosing loop's binding (§4.7)
  return ok;
}

std::vector<std::size_t> Interpreter::point_tour(Cell start, const Area& cells) {
  // A deterministic planner gives the same order for the same request: `strict` and `possible`
  // run a loop once as a trial and again for real, so the last order is reused (a tour over the
  // 16k cells of a 128^2 world is most of such a query).
  if (traits_.deterministic && last_tour_.valid && last_tour_.start == start &&
      last_tour_.cells == cells)
    return last_tour_.order;
  sdk::TourResult tour = planner_.tour(geometry_, start, cells, stop_);
  if (tour.status == sdk::PlanStatus::stopped) tick();
  if (tour.status != sdk::PlanStatus::found || tour.order.size() != cells.size())
    throw sdk::Error(sdk::codes::kExecution,
                     "the planner gave no visiting order for 'foreach point'");
  if (traits_.deterministic) {
    last_tour_.valid = true;
    last_tour_.start = start;
    last_tour_.cells = cells;
    last_tour_.order = tour.order;
  }
  return std::move(tour.order);
}

bool Interpreter::exec_foreach_area(const Node& n, WorldState& s, Sinks& out) {
  Collection areas = collection(*n.kids[0], s);
  if (areas.empty()) return true;
  // §8: one representative per area, the cell nearest to the robot by path; the tour orders
  // the reachable areas, the rest follow in collection order.
  std::vector<Cell> reps;
  std::vector<std::size_t> reachable, unreachable;
  for (std::size_t i = 0; i < areas.size(); ++i) {
    if (sdk::areas::contains(areas[i], s.robot)) {
      reps.push_back(s.robot);
      reachable.push_back(i);
      continue;
    }
    const sdk::PathResult r = plan(s.robot, areas[i], nullptr);
    if (r.status == sdk::PlanStatus::found) {
      reps.push_back(r.target);
      reachable.push_back(i);
    } else {
      unreachable.push_back(i);
    }
  }
  std::vector<std::size_t> order;
  order.reserve(areas.size());
  if (!reps.empty()) {
    const sdk::TourResult tour = planner_.tour(geometry_, s.robot, reps, stop_);
    if (tour.status == sdk::PlanStatus::stopped) tick();
    if (tour.status != sdk::PlanStatus::found || tour.order.size() != reps.size())
      throw sdk::Error(sdk::codes::kExecution,
                       "the planner gave no visiting order for 'foreach area'");
    for (std::size_t k : tour.order) order.push_back(reachable[k]);
  }
  order.insert(order.end(), unreachable.begin(), unreachable.end());
  bool ok = true;
  area_vars_.emplace_back();
  for (std::size_t i : order) {
    area_vars_.back() = std::move(areas[i]);
    ok = exec(*n.kids[1], s, out) && ok;
  }
  area_vars_.pop_back();
  return ok;
}

}  // namespace flipper::language::detail
