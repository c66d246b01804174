// Alternative tie choices for proofs (tie_proofs.hpp), guided by the logged next world. Items:
// the items the log shows picked (dropped) move to the front of the world's item lists, so
// `pick`/`drop` take one of them when it is eligible (§8 takes the first eligible item). Cells
// and loops: a planner wrapper that, among equally near goals, takes one the log shows visited
// (the robot's cell, cells where items were dropped) instead of the smallest, or orders a loop
// so that it ends at the logged robot cell (tour T, §8, is one order of many). Only tie choices
// change: every re-execution is the program's own semantics, checked against the whole world.
#include "tie_proofs.hpp"

#include <algorithm>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/executor.hpp"

namespace flipper::corpus::detail {

namespace {

// What the logged next world shows, to guide the alternative choices: the robot's cell, cells
// where items newly lie, and items newly held or newly lying.
struct LogHints {
  sdk::Cell robot;
  sdk::Area new_floor_cells;
  std::vector<std::string> new_held, new_floor;  // "colour shape"
};

struct Alternative {
  bool logged_items = false;          // pick/drop: items the log shows moved come first
  bool logged_nearest = false;        // equally near goals: one the log shows visited
  std::optional<sdk::Cell> tour_end;  // loops end at this cell when it is a point of the loop
};

class ProofPlanner : public sdk::Planner {
 public:
  ProofPlanner(const sdk::Planner& real, Alternative alt, const LogHints& log)
      : real_(real), alt_(alt), visited_(log.new_floor_cells) {
    visited_.push_back(log.robot);
    sdk::areas::normalize(visited_);
  }

 protected:
  sdk::PathResult do_plan(const sdk::Geometry& g, const sdk::PathRequest& req,
                          const sdk::StopCondition& stop) const override {
    sdk::PathResult r = real_.plan(g, req, stop);
    if (!alt_.logged_nearest || r.status != sdk::PlanStatus::found || req.goals == nullptr)
      return r;
    // Another goal as near as the chosen one, among the cells the log shows visited.
    const sdk::Area wanted = sdk::areas::intersect(*req.goals, visited_);
    if (wanted.empty() || sdk::areas::contains(wanted, r.target)) return r;
    sdk::PathRequest other = req;
    other.goals = &wanted;
    sdk::PathResult alt = real_.plan(g, other, stop);
    if (alt.status == sdk::PlanStatus::found && alt.path.size() == r.path.size()) return alt;
    return r;
  }
  sdk::TourResult do_tour(const sdk::Geometry& g, sdk::Cell start,
                          const std::vector<sdk::Cell>& points,
                          const sdk::StopCondition& stop) const override {
    sdk::TourResult t = real_.tour(g, start, points, stop);
    if (!alt_.tour_end || t.status != sdk::PlanStatus::found) return t;
    auto last = std::find_if(t.order.begin(), t.order.end(),
                             [&](std::size_t i) { return points[i] == *alt_.tour_end; });
    if (last != t.order.end()) std::rotate(last, last + 1, t.order.end());
    return t;
  }
  sdk::PlannerTraits do_traits() const override { return real_.traits(); }

 private:
  const sdk::Planner& real_;
  Alternative alt_;
  sdk::Area visited_;
};

std::string name_of(const sdk::ItemInfo& i) {
  return i.color + " " + i.shape;
}

/// Items the log shows moved come first (stable): `pick` and `drop` take the first eligible
/// item (§8), so they now take one the log shows picked (dropped) when one is eligible.
sdk::WorldState with_logged_items_first(sdk::WorldState w, const LogHints& log) {
  auto in = [](const std::vector<std::string>& names, const sdk::ItemInfo& i) {
    return std::find(names.begin(), names.end(), name_of(i)) != names.end();
  };
  std::stable_partition(w.items.begin(), w.items.end(),
                        [&](const sdk::LyingItem& li) { return in(log.new_held, li.item); });
  std::stable_partition(w.held.begin(), w.held.end(),
                        [&](const sdk::ItemInfo& i) { return in(log.new_floor, i); });
  return w;
}

/// Entries of `after` not in `before` (both sorted multisets).
std::vector<std::string> added(const std::vector<std::string>& before,
                               const std::vector<std::string>& after) {
  std::vector<std::string> out;
  std::set_difference(after.begin(), after.end(), before.begin(), before.end(),
                      std::back_inserter(out));
  return out;
}

LogHints hints(const WorldSnapshot& was, const WorldSnapshot& want) {
  LogHints h;
  h.robot = {want.x, want.y, 0};
  h.new_held = added(was.held, want.held);
  for (const auto& entry : added(was.floor, want.floor)) {  // "x,y colour shape"
    const auto comma = entry.find(','), space = entry.find(' ');
    h.new_floor_cells.push_back(
        {std::stoi(entry.substr(0, comma)), std::stoi(entry.substr(comma + 1, space)), 0});
    h.new_floor.push_back(entry.substr(space + 1));
  }
  sdk::areas::normalize(h.new_floor_cells);
  return h;
}

bool reproduces(const sdk::Program& program, const sdk::WorldState& start,
                const sdk::Planner& planner, const Alternative& alt, const LogHints& log,
                const WorldSnapshot& want) {
  // Borrowed: the wrapper lives on this stack frame for the whole run.
  const ProofPlanner proof(planner, alt, log);
  const kernel::Executor exec(kernel::PluginRef<const sdk::Planner>::borrowed(proof));
  const sdk::Outcome o =
      exec.run(program, alt.logged_items ? with_logged_items_first(start, log) : start);
  return !o.error && snapshot(o.world) == want;
}

}  // namespace

std::optional<AcceptClass> prove_tie(const sdk::Program& program, const sdk::WorldState& start,
                                     const sdk::Planner& planner, const WorldSnapshot& want) {
  const LogHints log = hints(snapshot(start), want);
  const sdk::Cell end = log.robot;
  const struct {
    Alternative alt;
    AcceptClass proves;
  } tries[] = {
      {{true, false, std::nullopt}, AcceptClass::item_choice},
      {{false, true, std::nullopt}, AcceptClass::nearest_cell},
      {{true, true, std::nullopt}, AcceptClass::nearest_cell},
      {{false, false, end}, AcceptClass::loop_order},
      {{true, false, end}, AcceptClass::loop_order},
      {{false, true, end}, AcceptClass::loop_order},
      {{true, true, end}, AcceptClass::loop_order},
  };
  for (const auto& t : tries)
    if (reproduces(program, start, planner, t.alt, log, want)) return t.proves;
  return std::nullopt;
}

}  // namespace flipper::corpus::detail
