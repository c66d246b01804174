// Primitive actions (core-language §4.4): move, visit, pick, drop. Each either succeeds and
// changes the state, or fails, changes nothing (§6) and reports one warning (§5).
#include <algorithm>
#include <memory>
#include <string>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "interpreter.hpp"
#include "nearest.hpp"

namespace flipper::language::detail {

using sdk::Area;
using sdk::Cell;
using sdk::Kind;
using sdk::Node;
using sdk::TraceStep;
using sdk::WorldState;

namespace {
// Canonical text of an action for its warning. Nodes are always owned by a Program, but the
// interpreter walks plain references; a non-owning alias renders without copying.
std::string text_of(const Node& n) {
  return sdk::render(sdk::Program(std::shared_ptr<const Node>(), &n));
}
}  // namespace

bool matches(const Node& n, const sdk::ItemInfo& info) {
  switch (n.kind) {
    case Kind::Item:
      return n.kids.empty() || matches(*n.kids[0], info);
    case Kind::Every:
      return matches(*n.kids[0], info);
    case Kind::FilterIs: {
      const Node& w = *n.kids[0];
      return w.kind == Kind::Shape ? info.shape == w.text : info.color == w.text;
    }
    case Kind::FilterAnd:
      return matches(*n.kids[0], info) && matches(*n.kids[1], info);
    case Kind::FilterOr:
      return matches(*n.kids[0], info) || matches(*n.kids[1], info);
    case Kind::FilterNot:
      return !matches(*n.kids[0], info);
    default:
      throw sdk::Error(sdk::codes::kExecution,
                       std::string("not an item: ") + sdk::kind_name(n.kind));
  }
}

std::string describe(const Node& n) {
  const Node& item = n.kind == Kind::Every ? *n.kids[0] : n;
  if (item.kids.empty()) return "item";
  const Node& f = *item.kids[0];
  if (f.kind == Kind::FilterIs) return f.kids[0]->text + " item";
  return "item " + text_of(f);
}

std::string cell_text(const sdk::Geometry& g, Cell c) {
  return sdk::to_string(c, g.dims());
}

void Interpreter::count_action() {
  if (++actions_ > limits_.action_budget)
    throw sdk::Error(sdk::codes::kBudgetExceeded,
                     "action budget exceeded: more than " + std::to_string(limits_.action_budget) +
                         " primitive actions (execution.action_budget)");
  if ((actions_ & 255u) == 0) tick();
}

bool Interpreter::fail(const Node& n, Sinks& out, const std::string& reason) {
  if (out.warnings != nullptr) {
    std::string w = "Could not complete the action: " + text_of(n);
    if (!reason.empty()) w += " (" + reason + ")";
    out.warnings->push_back(std::move(w));
  }
  return false;
}

sdk::PathResult Interpreter::plan(Cell start, const Area& goals, const Area* avoid,
                                  std::size_t* distance) {
  sdk::PathRequest req;
  req.start = start;
  req.goals = &goals;
  req.avoid = (avoid != nullptr && !avoid->empty()) ? avoid : nullptr;
  Area nearest;
  if (!traits_.optimal && (goals.size() > 1 || distance != nullptr)) {
    // Which goal is semantics (§4.4): decided here from path distances, whatever the planner.
    const NearestGoal n = nearest_goal(geometry_, start, goals, req.avoid, stop_);
    if (n.status != sdk::PlanStatus::found) {
      if (n.status == sdk::PlanStatus::stopped) tick();
      sdk::PathResult none;  // the executor's own search proved it: no planner message
      none.status = n.status;
      return none;
    }
    nearest = {n.target};
    req.goals = &nearest;
    if (distance != nullptr) *distance = n.distance;
  }
  // Checked before anything follows it (docs/plugins-untrusted.md): invalid_plan otherwise.
  sdk::PathResult r = planner_.plan(geometry_, req, stop_);
  if (r.status == sdk::PlanStatus::stopped) tick();  // the deadline fired inside the planner
  if (distance != nullptr && traits_.optimal) *distance = r.path.size();
  return r;
}

std::string Interpreter::unproven(const sdk::PathResult& r) const {
  if (r.message.empty() || (r.status != sdk::PlanStatus::stopped && !traits_.sampling)) return {};
  return "; the planner: " + r.message;
}

void Interpreter::follow(const sdk::PathResult& path, WorldState& s, Sinks& out) {
  if (out.trace != nullptr)
    for (const Cell& c : path.path) out.trace->push_back(TraceStep{TraceStep::Act::move, c, {}});
  s.robot = path.target;
}

bool Interpreter::move(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const std::string& word = n.kids[0]->text;
  auto offset = geometry_.direction(word);
  if (!offset)
    throw sdk::Error(sdk::codes::kExecution, "this world has no direction '" + word + "'");
  const Cell to = s.robot + *offset;
  if (!geometry_.is_free(to))
    return fail(n, out,
                out.warnings
                    ? cell_text(geometry_, to) +
                          (geometry_.in_bounds(to) ? " is a wall" : " is outside the world")
                    : std::string());
  s.robot = to;
  if (out.trace != nullptr) out.trace->push_back(TraceStep{TraceStep::Act::move, to, {}});
  return true;
}

bool Interpreter::visit_point(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const Cell p = point(*n.kids[0], s);
  if (p == s.robot) return true;  // the start cell is exempt from the avoid set too
  if (!geometry_.is_free(p))
    return fail(n, out,
                out.warnings ? cell_text(geometry_, p) +
                                   (geometry_.in_bounds(p) ? " is a wall" : " is outside the world")
                             : std::string());
  Area avoid;
  if (n.kids.size() > 1) {
    avoid = area(*n.kids[1], s);
    if (sdk::areas::contains(avoid, p))
      return fail(n, out,
                  out.warnings ? cell_text(geometry_, p) + " lies in the avoided area" : "");
  }
  const Area goal{p};
  const sdk::PathResult r = plan(s.robot, goal, &avoid);
  if (r.status != sdk::PlanStatus::found) {
    std::string why;
    if (out.warnings) {
      why = cell_text(geometry_, p) + " is unreachable";
      if (n.kids.size() > 1) why += " while avoiding " + text_of(*n.kids[1]);
      why += unproven(r);
    }
    return fail(n, out, why);
  }
  follow(r, s, out);
  return true;
}

bool Interpreter::visit_area(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const Area goals = area(*n.kids[0], s);
  if (sdk::areas::contains(goals, s.robot)) return true;
  Area avoid;
  if (n.kids.size() > 1) avoid = sdk::areas::subtract(area(*n.kids[1], s), goals);
  const sdk::PathResult r = plan(s.robot, goals, &avoid);
  if (r.status != sdk::PlanStatus::found) {
    std::string why;
    if (out.warnings) {
      const bool any_free = std::any_of(goals.begin(), goals.end(),
                                        [&](const Cell& c) { return geometry_.is_free(c); });
      if (!any_free) {
        why = "no free cell in " + text_of(*n.kids[0]);
      } else {
        why = text_of(*n.kids[0]) + " is unreachable";
        if (n.kids.size() > 1) why += " while avoiding " + text_of(*n.kids[1]);
        why += unproven(r);
      }
    }
    return fail(n, out, why);
  }
  follow(r, s, out);
  return true;
}

bool Interpreter::visit_collection(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const Collection areas = collection(*n.kids[0], s);
  Area avoid_all;
  if (n.kids.size() > 1) avoid_all = area(*n.kids[1], s);
  // §4.4 [decision]: the shortest candidate over all areas; ties: smallest target, then the
  // first area in collection order.
  sdk::PathResult best;
  std::size_t best_distance = 0;
  bool found = false;
  for (const Area& x : areas) {
    if (sdk::areas::contains(x, s.robot)) return true;
    const Area avoid = n.kids.size() > 1 ? sdk::areas::subtract(avoid_all, x) : Area{};
    std::size_t distance = 0;
    sdk::PathResult r = plan(s.robot, x, &avoid, &distance);
    if (r.status != sdk::PlanStatus::found) continue;
    if (!found || distance < best_distance ||
        (distance == best_distance && r.target < best.target)) {
      best = std::move(r);
      best_distance = distance;
      found = true;
    }
  }
  if (!found) {
    std::string why;
    if (out.warnings) {
      why = areas.empty() ? text_of(*n.kids[0]) + " has no areas"
                          : "no area of " + text_of(*n.kids[0]) + " is reachable";
      if (!areas.empty() && n.kids.size() > 1) why += " while avoiding " + text_of(*n.kids[1]);
    }
    return fail(n, out, why);
  }
  follow(best, s, out);
  return true;
}

bool Interpreter::action_succeeds(const Node& n, const WorldState& s) {
  count_action();  // as the action itself would
  if (n.kind == Kind::Move) {
    const std::string& word = n.kids[0]->text;
    const auto offset = geometry_.direction(word);
    if (!offset)
      throw sdk::Error(sdk::codes::kExecution, "this world has no direction '" + word + "'");
    return geometry_.is_free(s.robot + *offset);
  }
  const Node& what = *n.kids[0];
  if (n.kind == Kind::Pick)
    return std::any_of(s.items.begin(), s.items.end(), [&](const sdk::LyingItem& li) {
      return li.at == s.robot && matches(what, li.item);
    });
  return std::any_of(s.held.begin(), s.held.end(),
                     [&](const sdk::ItemInfo& h) { return matches(what, h); });
}

bool Interpreter::pick(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const Node& what = *n.kids[0];
  const bool every = what.kind == Kind::Every;
  bool any = false;
  // §8: eligible items in world order; a picked item joins the end of the held list. One
  // compacting pass (erasing one by one was quadratic: 30,000 items on a cell took seconds).
  std::size_t keep = 0;
  for (std::size_t i = 0; i < s.items.size(); ++i) {
    if ((i & 4095u) == 4095u) tick();
    sdk::LyingItem& li = s.items[i];
    if ((every || !any) && li.at == s.robot && matches(what, li.item)) {
      any = true;
      if (out.trace != nullptr)
        out.trace->push_back(TraceStep{TraceStep::Act::pick, li.at, li.item});
      s.held.push_back(std::move(li.item));
    } else {
      if (keep != i) s.items[keep] = std::move(li);
      ++keep;
    }
  }
  s.items.resize(keep);
  if (!any) return fail(n, out, out.warnings ? "no " + describe(what) + " here" : "");
  return true;
}

bool Interpreter::drop(const Node& n, WorldState& s, Sinks& out) {
  count_action();
  const Node& what = *n.kids[0];
  const bool every = what.kind == Kind::Every;
  bool any = false;
  // §8: held items in pick order; a dropped item goes to the end of the lying items (one
  // compacting pass, as in pick).
  std::size_t keep = 0;
  for (std::size_t i = 0; i < s.held.size(); ++i) {
    if ((i & 4095u) == 4095u) tick();
    if ((every || !any) && matches(what, s.held[i])) {
      any = true;
      if (out.trace != nullptr)
        out.trace->push_back(TraceStep{TraceStep::Act::drop, s.robot, s.held[i]});
      s.items.push_back(sdk::LyingItem{std::move(s.held[i]), s.robot});
    } else {
      if (keep != i) s.held[keep] = std::move(s.held[i]);
      ++keep;
    }
  }
  s.held.resize(keep);
  if (!any) return fail(n, out, out.warnings ? "no " + describe(what) + " held" : "");
  return true;
}

}  // namespace flipper::language::detail
