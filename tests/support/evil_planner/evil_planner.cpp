// evil_planner: a planner that misbehaves on purpose, for the tests of what the kernel checks and
// contains (docs/plugins-untrusted.md). In mode `ok` it plans correctly (breadth-first, the core
// language's tie rules for neighbours); every other mode misbehaves on the `on_call`-th call to
// plan() counted per instance (0: every call) and behaves before it:
//   throw   throws std::runtime_error from plan()
//   wall    returns a path through the first wall cell beside the straight line (11 steps for
//           "visit room1" on the study map instead of 13)
//   outside returns a path that leaves the world
//   jump    returns a path whose second step jumps two cells
//   goal    returns a correct path to a cell that is not a goal
//   segv    dereferences a null pointer
//   abort   calls std::abort()
//   hang    spins (on the CPU) until the process is killed
//   tour    tour() returns an order that is not a permutation
// `on_target_x=X` (-1: any) limits the misbehaviour to requests whose correct path ends in
// column X, so one user's request can crash while another's is answered (in a child process each
// call sees the count of calls before isolation began: `on_call` counts in-process calls only).
// Tests build it with flipper_add_plugin (tests/support/evil_planner/CMakeLists.txt) and select
// it with --set plugin_paths=[build/tests/plugins/evil] --set planner.plugin=evil_planner.
#include <atomic>
#include <cstdlib>
#include <deque>
#include <map>
#include <numeric>
#include <stdexcept>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/planner.hpp"

namespace evil_planner {
namespace {

using flipper::sdk::Area;
using flipper::sdk::Cell;
using flipper::sdk::Geometry;
namespace sdk = flipper::sdk;
namespace param = flipper::sdk::param;

enum class Mode { ok, throws, wall, outside, jump, goal, segv, abort_, hang, tour };
constexpr param::Choice<Mode, 10> kMode{
    "mode",
    Mode::ok,
    {"ok", "throw", "wall", "outside", "jump", "goal", "segv", "abort", "hang", "tour"},
    "how to misbehave (tests/support/evil_planner/evil_planner.cpp)"};
constexpr param::Int<std::int64_t> kOnCall{"on_call", 0, 0, std::nullopt,
                                           "misbehave on this call to plan() only (0: every call)"};
constexpr param::Int<std::int64_t> kOnTargetX{
    "on_target_x", -1, -1, std::nullopt,
    "misbehave only when the correct path ends in this column (-1: any)"};

// Breadth-first search from start to the nearest goal, neighbours in the geometry's order.
sdk::PathResult bfs(const Geometry& g, const sdk::PathRequest& req) {
  sdk::PathResult r;
  std::map<Cell, Cell> parent;
  std::deque<Cell> open{req.start};
  parent[req.start] = req.start;
  while (!open.empty()) {
    const Cell c = open.front();
    open.pop_front();
    ++r.expansions;
    if (sdk::areas::contains(*req.goals, c) && g.is_free(c)) {
      r.status = sdk::PlanStatus::found;
      r.target = c;
      for (Cell p = c; p != req.start; p = parent[p]) r.path.insert(r.path.begin(), p);
      return r;
    }
    for (const Cell& d : g.neighbour_offsets()) {
      const Cell n = c + d;
      if (!g.is_free(n) || parent.count(n) != 0) continue;
      if (req.avoid != nullptr && sdk::areas::contains(*req.avoid, n)) continue;
      parent[n] = c;
      open.push_back(n);
    }
  }
  r.message = "no path";
  return r;
}

// A straight walk in x, then in y, from start to the target, walls or not.
std::vector<Cell> straight(Cell from, Cell to) {
  std::vector<Cell> path;
  while (from.x != to.x) {
    from.x += from.x < to.x ? 1 : -1;
    path.push_back(from);
  }
  while (from.y != to.y) {
    from.y += from.y < to.y ? 1 : -1;
    path.push_back(from);
  }
  return path;
}

class EvilPlanner final : public sdk::Planner {
 public:
  explicit EvilPlanner(const sdk::Params& p)
      : mode_(param::get(p, kMode)),
        on_call_(param::get(p, kOnCall)),
        on_target_x_(param::get(p, kOnTargetX)) {}
  static sdk::ParamSchema schema() { return param::schema(kMode, kOnCall, kOnTargetX); }

 protected:
  sdk::PathResult do_plan(const Geometry& g, const sdk::PathRequest& req,
                          const sdk::StopCondition&) const override {
    const std::int64_t call = ++calls_;
    sdk::PathResult r = bfs(g, req);
    if (mode_ == Mode::ok || (on_call_ != 0 && call != on_call_)) return r;
    if (on_target_x_ >= 0 && (r.status != sdk::PlanStatus::found || r.target.x != on_target_x_))
      return r;
    switch (mode_) {
      case Mode::throws:
        throw std::runtime_error("evil_planner: thrown on purpose");
      case Mode::wall: {
        // The straight walk to the goal the correct path reached: it crosses a wall whenever
        // the correct path had to go around one.
        if (r.status == sdk::PlanStatus::found) r.path = straight(req.start, r.target);
        return r;
      }
      case Mode::outside:
        r.status = sdk::PlanStatus::found;
        r.path.insert(r.path.begin(), Cell{req.start.x, -1, req.start.z});
        return r;
      case Mode::jump:
        if (r.status == sdk::PlanStatus::found && r.path.size() >= 2) r.path.erase(r.path.begin());
        return r;
      case Mode::goal:
        if (r.status == sdk::PlanStatus::found && !r.path.empty()) r.path.pop_back();
        return r;
      case Mode::segv: {
        volatile int* null = nullptr;
        *null = 1;  // NOLINT: a crash on purpose
        return r;
      }
      case Mode::abort_:
        std::abort();
      case Mode::hang: {
        volatile std::uint64_t spin = 0;
        for (;;) spin = spin + 1;
      }
      case Mode::tour:
      case Mode::ok:
        return r;
    }
    return r;
  }

  sdk::TourResult do_tour(const Geometry&, Cell, const std::vector<Cell>& points,
                          const sdk::StopCondition&) const override {
    sdk::TourResult t;
    t.order.resize(points.size());
    std::iota(t.order.begin(), t.order.end(), 0);
    if (mode_ == Mode::tour && !t.order.empty()) t.order.back() = 0;  // 0 twice: no permutation
    return t;
  }

  sdk::PlannerTraits do_traits() const override {
    sdk::PlannerTraits t;
    t.supports_3d = true;
    return t;
  }

 private:
  Mode mode_;
  std::int64_t on_call_;
  std::int64_t on_target_x_;
  mutable std::atomic<std::int64_t> calls_{0};
};

}  // namespace
}  // namespace evil_planner

FLIPPER_PLUGIN(evil_planner::EvilPlanner, planner, "evil_planner", FLIPPER_PLUGIN_VERSION,
               "A planner that misbehaves on purpose (tests only)")
