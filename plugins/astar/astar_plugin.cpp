// astar: the reference planner. Paths are breadth-first (every step costs 1), from the start to
// the nearest free goal cell, with the core language's tie rules (core-language §8); tours are
// §8's tour T (Christofides on shortest-path distances, then 2-opt and Or-opt on the open path).
// Works on any Geometry: the neighbourhood comes from geometry.neighbour_offsets().
#include <algorithm>
#include <limits>
#include <numeric>

#include "distance_cache.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/planner.hpp"
#include "grid_search.hpp"
#include "tour_solver.hpp"

namespace flipper::plugins::astar {
namespace {

using sdk::Cell;

namespace param = sdk::param;

enum class Heuristic { none, manhattan };  // in the order of kHeuristic's names
constexpr param::Choice<Heuristic, 2> kHeuristic{
    "heuristic",
    Heuristic::none,
    {"none", "manhattan"},
    "none: breadth-first search, paths follow the core language's tie rule; manhattan: A* for "
    "single-cell goals, equally short paths but possibly a different one of several shortest "
    "paths"};
constexpr param::Int<std::uint64_t> kMaxExpansions{
    "max_expansions", 0, 0, std::nullopt,
    "expansion budget per search, on top of the caller's stop condition (0: none)"};
constexpr param::Int<std::int64_t> kMaxTourPoints{
    "max_tour_points", 2000, 1, std::nullopt,
    "tours over more reachable points than this use greedy nearest-neighbour order instead of "
    "tour T (which needs a distance matrix of that size squared)"};
constexpr param::Bool kTwoOpt{"two_opt", true, "improve tours with 2-opt moves"};
constexpr param::Bool kOrOpt{"or_opt", true,
                             "improve tours with Or-opt moves (segments of 1-3 points)"};

class AStarPlanner final : public sdk::Planner {
 public:
  explicit AStarPlanner(const sdk::Params& p)
      : budget_(param::get(p, kMaxExpansions) > 0 ? param::get(p, kMaxExpansions)
                                                  : std::numeric_limits<std::uint64_t>::max()),
        two_opt_(param::get(p, kTwoOpt)),
        or_opt_(param::get(p, kOrOpt)),
        manhattan_(param::get(p, kHeuristic) == Heuristic::manhattan),
        max_tour_points_(param::get(p, kMaxTourPoints)) {}

  static sdk::ParamSchema schema() {
    return param::schema(kHeuristic, kMaxExpansions, kMaxTourPoints, kTwoOpt, kOrOpt);
  }

 protected:
  sdk::PathResult do_plan(const sdk::Geometry& g, const sdk::PathRequest& req,
                          const sdk::StopCondition& stop) const override {
    // Goals present, start in bounds, stop not yet fired: Planner::plan checked.
    sdk::PathResult r;
    // The buffers are this instance's, reused between calls: one request at a time per
    // instance (flipper/sdk/plugin.hpp), so no lock.
    if (!search_.prepare(g)) {
      r.status = sdk::PlanStatus::invalid;
      r.message = "the world is too large for 32-bit cell indexes";
      return r;
    }
    if (req.avoid != nullptr) search_.block(*req.avoid, req.start);
    if (manhattan_ && req.goals->size() == 1)
      return search_.shortest_path_astar(req.start, req.goals->front(), stop, budget_);
    return search_.shortest_path(req.start, *req.goals, stop, budget_);
  }

  sdk::TourResult do_tour(const sdk::Geometry& g, Cell start, const std::vector<Cell>& points,
                          const sdk::StopCondition& stop) const override {
    sdk::TourResult r;
    // Point indexes in (cell, index) order: the order of unreachable points, and the grouping
    // of points that share a cell.
    std::vector<std::size_t> by_cell(points.size());
    std::iota(by_cell.begin(), by_cell.end(), 0);
    // Areas come sorted (the kernel normalizes them), and then the identity is the stable order.
    // Otherwise sorting millions of points takes seconds: the comparison polls the stop
    // condition, so the caller's deadline holds here too.
    if (!std::is_sorted(points.begin(), points.end())) {
      struct SortStopped {};
      std::uint64_t comparisons = 0;
      try {
        std::stable_sort(by_cell.begin(), by_cell.end(), [&](std::size_t a, std::size_t b) {
          if ((++comparisons & 0xFFFFu) == 0 && stop.expired()) throw SortStopped{};
          return points[a] < points[b];
        });
      } catch (const SortStopped&) {
        std::iota(by_cell.begin(), by_cell.end(), 0);
        return stopped(r, by_cell);
      }
    }
    if (points.empty()) return r;
    if (stop.expired()) return stopped(r, by_cell);
    if (!g.in_bounds(start) || !search_.prepare(g)) {
      r.status = sdk::PlanStatus::invalid;
      r.order = by_cell;
      return r;
    }
    // Distinct free point cells, sorted; then which of them the start reaches.
    std::vector<Cell> cells;
    for (std::size_t i : by_cell)
      if (g.is_free(points[i]) && (cells.empty() || cells.back() != points[i]))
        cells.push_back(points[i]);
    std::uint64_t expansions = 0;
    if (stop.expired()) return stopped(r, by_cell);
    // Distances remembered from earlier tours on this geometry (distance_cache.hpp). A start on
    // a wall is passable only as a start, which breaks symmetry: no caching then; nor under an
    // expansion budget, whose outcome must not depend on earlier requests.
    const bool cache = budget_ == std::numeric_limits<std::uint64_t>::max() &&
                       stop.max_expansions == std::numeric_limits<std::uint64_t>::max() &&
                       cache_.use(g) && g.is_free(start);
    std::vector<std::int32_t> from_start(cells.size(), -1);
    if (!(cache && DistanceCache::fits(cells.size()) && cached_row(start, cells, 0, from_start))) {
      std::fill(from_start.begin(), from_start.end(), -1);
      search_.set_targets(cells);
      if (!search_.distances(start, -1, from_start.data(), stop, budget_, expansions)) {
        search_.clear_targets();
        return stopped(r, by_cell);
      }
      search_.clear_targets();
      if (cache && DistanceCache::fits(cells.size()))
        for (std::size_t k = 0; k < cells.size(); ++k) cache_.store(start, cells[k], from_start[k]);
    }
    // Vertices: the start and the reachable point cells, numbered in (x, y, z) order. `cells` is
    // sorted, so the start is merged in where it belongs (no sort: millions of cells took
    // seconds that the deadline did not cover).
    std::vector<Cell> vertices;
    vertices.reserve(cells.size() + 1);
    bool start_placed = false;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (from_start[k] < 0 || cells[k] == start) continue;
      if (!start_placed && start < cells[k]) {
        vertices.push_back(start);
        start_placed = true;
      }
      vertices.push_back(cells[k]);
    }
    if (!start_placed) vertices.push_back(start);
    // Freed now rather than at return: on millions of points they are a sixth of the peak.
    std::vector<Cell>().swap(cells);
    std::vector<std::int32_t>().swap(from_start);
    const int n = static_cast<int>(vertices.size());
    const int s = static_cast<int>(std::lower_bound(vertices.begin(), vertices.end(), start) -
                                   vertices.begin());
    std::vector<int> path;
    if (n > max_tour_points_) {
      if (stop.expired()) return stopped(r, by_cell);
      if (!greedy_path(vertices, s, stop, expansions, path, r.length)) return stopped(r, by_cell);
      r.status = sdk::PlanStatus::found;
      return finish(r, path, vertices, points, by_cell);
    }
    DistanceMatrix m;
    m.n = n;
    m.d.assign(static_cast<std::size_t>(n) * n, 0.0);
    search_.set_targets(vertices);
    std::vector<std::int32_t> row(n);
    const bool cache_rows = cache && DistanceCache::fits(vertices.size());
    for (int v = 0; v < n; ++v) {
      std::fill(row.begin(), row.end(), -1);
      if (!(cache_rows && cached_row(vertices[v], vertices, v + 1, row))) {
        std::fill(row.begin(), row.end(), -1);
        if (!search_.distances(vertices[v], v, row.data(), stop, budget_, expansions)) {
          search_.clear_targets();
          return stopped(r, by_cell);
        }
        if (cache_rows)
          for (int u = v + 1; u < n; ++u) cache_.store(vertices[v], vertices[u], row[u]);
      }
      for (int u = v + 1; u < n; ++u) {
        // The neighbourhood is symmetric in every world we know; an unreachable pair (a
        // one-way world) is made very long rather than breaking the tour.
        const double d = row[u] >= 0 ? row[u] : 1e9;
        m.d[static_cast<std::size_t>(v) * n + u] = m.d[static_cast<std::size_t>(u) * n + v] = d;
      }
    }
    search_.clear_targets();
    path = open_path_from_cycle(m, christofides_cycle(m, s));
    const bool complete =
        improve_open_path(m, path, two_opt_, or_opt_, [&] { return stop.should_stop(expansions); });
    r.status = complete ? sdk::PlanStatus::found : sdk::PlanStatus::stopped;
    r.length = open_length(m, path);
    return finish(r, path, vertices, points, by_cell);
  }

  // Fills row[k] for k >= from with cached distances from `a` to cells[k]; false if any is
  // missing.
  bool cached_row(Cell a, const std::vector<Cell>& cells, std::size_t from,
                  std::vector<std::int32_t>& row) const {
    for (std::size_t k = from; k < cells.size(); ++k)
      if (!cache_.find(a, cells[k], row[k])) return false;
    return true;
  }

  // Greedy nearest neighbour from vertex s by repeated breadth-first searches (ties: smallest
  // cell): for point sets too large for a distance matrix.
  bool greedy_path(const std::vector<Cell>& vertices, int s, const sdk::StopCondition& stop,
                   std::uint64_t& expansions, std::vector<int>& path, double& length) const {
    search_.set_goals(vertices);
    search_.unset_goal(vertices[s]);
    path.assign(1, s);
    length = 0;
    Cell at = vertices[s];
    for (std::size_t k = 1; k < vertices.size(); ++k) {
      Cell next;
      bool halted = false;
      const std::int32_t d = search_.nearest_goal(at, next, stop, budget_, expansions, halted);
      if (d < 0) return false;  // stopped (every vertex is reachable)
      search_.unset_goal(next);
      path.push_back(static_cast<int>(std::lower_bound(vertices.begin(), vertices.end(), next) -
                                      vertices.begin()));
      length += d;
      at = next;
    }
    return true;
  }

  // Points per vertex in path order, then the unreachable ones in (cell, index) order.
  static sdk::TourResult& finish(sdk::TourResult& r, const std::vector<int>& path,
                                 const std::vector<Cell>& vertices, const std::vector<Cell>& points,
                                 const std::vector<std::size_t>& by_cell) {
    std::vector<char> placed(points.size(), 0);
    auto first_at = [&](const Cell& c) {
      return std::lower_bound(by_cell.begin(), by_cell.end(), c,
                              [&](std::size_t i, const Cell& cc) { return points[i] < cc; });
    };
    for (int v : path)
      for (auto it = first_at(vertices[v]); it != by_cell.end() && points[*it] == vertices[v];
           ++it) {
        r.order.push_back(*it);
        placed[*it] = 1;
      }
    for (std::size_t i : by_cell)
      if (!placed[i]) r.order.push_back(i);
    return r;
  }

  sdk::PlannerTraits do_traits() const override {
    sdk::PlannerTraits t;
    t.supports_2d = true;
    t.supports_3d = true;
    t.optimal = true;
    t.deterministic = true;
    return t;
  }

 private:
  static sdk::TourResult stopped(sdk::TourResult& r, const std::vector<std::size_t>& by_cell) {
    r.status = sdk::PlanStatus::stopped;
    r.order = by_cell;
    r.length = 0;
    return r;
  }

  std::uint64_t budget_;
  bool two_opt_;
  bool or_opt_;
  bool manhattan_;
  std::int64_t max_tour_points_;
  // Scratch state of this instance's calls (one at a time, flipper/sdk/plugin.hpp).
  mutable GridSearch search_;
  mutable DistanceCache cache_;
};

}  // namespace
}  // namespace flipper::plugins::astar

FLIPPER_PLUGIN(flipper::plugins::astar::AStarPlanner, planner, "astar", FLIPPER_PLUGIN_VERSION,
               "Breadth-first shortest paths with the core language's tie rules; Christofides "
               "tours improved by 2-opt and Or-opt")
