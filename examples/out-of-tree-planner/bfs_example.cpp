// bfs_example: breadth-first search over the world's cell graph. Paths are shortest in steps;
// among equally near goals the smallest (x, y, z) wins, and neighbours are expanded in the
// geometry's tie order, as the planner contract asks. Tours are greedy nearest-neighbour.
// Its one parameter is declared once, as a typed handle (flipper/sdk/config_handles.hpp).
// Threads: the kernel calls an instance for one request at a time (flipper/sdk/plugin.hpp), so an
// instance may keep scratch buffers between calls without a lock; this one allocates per call.
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/planner.hpp>
#include <flipper/sdk/plugin.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace bfs_example {

using flipper::sdk::Area;
using flipper::sdk::Cell;
using flipper::sdk::Geometry;

namespace param = flipper::sdk::param;

// Name, default, range and description, written once: the schema and the constructor use it.
constexpr param::Int<std::uint64_t> kMaxExpansions{
    "max_expansions", 0, 0, std::nullopt,
    "cells one search may expand before it gives up (0: no limit but the caller's stop)"};

class BfsExample : public flipper::sdk::Planner {
 public:
  explicit BfsExample(const flipper::sdk::Params& p)
      : max_expansions_(param::get(p, kMaxExpansions)) {}
  static flipper::sdk::ParamSchema schema() { return param::schema(kMaxExpansions); }

 protected:
  flipper::sdk::PathResult do_plan(const Geometry& g, const flipper::sdk::PathRequest& req,
                                   const flipper::sdk::StopCondition& stop) const override {
    flipper::sdk::PathResult r;
    if (req.goals == nullptr || req.goals->empty()) {
      r.status = flipper::sdk::PlanStatus::invalid;
      r.message = "empty goal set";
      return r;
    }
    if (!g.is_free(req.start)) {
      r.message = "start is not free";
      return r;
    }
    const auto is_goal = [&](Cell c) {
      return std::binary_search(req.goals->begin(), req.goals->end(), c) && g.is_free(c);
    };
    const auto avoided = [&](Cell c) {
      return req.avoid != nullptr && std::binary_search(req.avoid->begin(), req.avoid->end(), c);
    };
    if (is_goal(req.start)) {
      r.status = flipper::sdk::PlanStatus::found;
      r.target = req.start;
      return r;
    }
    constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> parent(g.cell_count(), kNone);
    const std::size_t start = g.index(req.start);
    parent[start] = start;
    std::vector<std::size_t> layer{start}, next;
    while (!layer.empty()) {
      std::size_t best = kNone;  // smallest goal cell of the next layer
      next.clear();
      for (std::size_t i : layer) {
        if (stop.should_stop(r.expansions) ||
            (max_expansions_ > 0 && r.expansions >= max_expansions_)) {
          r.status = flipper::sdk::PlanStatus::stopped;
          return r;
        }
        ++r.expansions;
        const Cell c = g.cell_at(i);
        for (const Cell& d : g.neighbour_offsets()) {
          const Cell n = c + d;
          if (!g.is_free(n) || avoided(n)) continue;
          const std::size_t k = g.index(n);
          if (parent[k] != kNone) continue;
          parent[k] = i;
          next.push_back(k);
          if (is_goal(n) && (best == kNone || n < g.cell_at(best))) best = k;
        }
      }
      if (best != kNone) {
        for (std::size_t k = best; k != start; k = parent[k]) r.path.push_back(g.cell_at(k));
        std::reverse(r.path.begin(), r.path.end());
        r.status = flipper::sdk::PlanStatus::found;
        r.target = g.cell_at(best);
        return r;
      }
      layer.swap(next);
    }
    r.message = "no path";
    return r;
  }

  flipper::sdk::TourResult do_tour(const Geometry& g, Cell start, const std::vector<Cell>& points,
                                   const flipper::sdk::StopCondition& stop) const override {
    flipper::sdk::TourResult t;
    std::vector<bool> done(points.size(), false);
    Cell at = start;
    for (std::size_t visited = 0; visited < points.size(); ++visited) {
      // The nearest remaining point by BFS steps (ties: smallest cell, then lowest index).
      Area goals;
      for (std::size_t i = 0; i < points.size(); ++i)
        if (!done[i]) goals.push_back(points[i]);
      std::sort(goals.begin(), goals.end());
      const auto r = do_plan(g, {at, &goals, nullptr}, stop);
      if (r.status == flipper::sdk::PlanStatus::stopped) t.status = r.status;
      if (r.status != flipper::sdk::PlanStatus::found) break;
      for (std::size_t i = 0; i < points.size(); ++i)
        if (!done[i] && points[i] == r.target) {
          done[i] = true;
          t.order.push_back(i);
          break;
        }
      t.length += static_cast<double>(r.path.size());
      at = r.target;
    }
    // Unreachable points last, in (x, y, z) order.
    std::vector<std::size_t> rest;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!done[i]) rest.push_back(i);
    std::stable_sort(rest.begin(), rest.end(),
                     [&](std::size_t a, std::size_t b) { return points[a] < points[b]; });
    t.order.insert(t.order.end(), rest.begin(), rest.end());
    return t;
  }

  flipper::sdk::PlannerTraits do_traits() const override {
    flipper::sdk::PlannerTraits t;
    t.supports_3d = true;  // BFS works on any neighbourhood the geometry defines
    return t;
  }

 private:
  const std::uint64_t max_expansions_;
};

}  // namespace bfs_example

FLIPPER_PLUGIN(bfs_example::BfsExample, planner, "bfs_example", FLIPPER_PLUGIN_VERSION,
               "Breadth-first search on the world's cell graph (out-of-tree example)")
