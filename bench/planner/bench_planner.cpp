// Planner benchmark: visits on random 1024 x 1024 grids with 30% walls (to one cell, and to the
// nearest of a set), tours over 10 / 100 / 1000 points, and tours on the study map's rooms, with
// each tour's length next to the original system's kind of tour: Christofides over straight-line
// distances from an arbitrary start, walked along real shortest paths. Prints medians.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <deque>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"
#include "study_world.hpp"
#include "tour_solver.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

// CPU time of this thread: the machine is shared, so wall time measures the neighbours too.
struct Clock {
  static double now_ms() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
  }
};
using TimePoint = double;
TimePoint start_clock() {
  return Clock::now_ms();
}
double ms_since(TimePoint t0) {
  return Clock::now_ms() - t0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

std::shared_ptr<const sdk::Geometry> random_grid(int size, double walls, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution wall(walls);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(size) * size);
  for (auto& m : mask) m = wall(rng) ? 0 : 1;
  return std::make_shared<const sdk::Geometry>(
      2, Cell{0, 0, 0}, Cell{size - 1, size - 1, 0}, std::move(mask),
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, Cell>>{});
}

// The cells of the largest connected free region (so benchmark queries have answers).
std::vector<Cell> largest_component(const sdk::Geometry& g) {
  std::vector<int> comp(g.cell_count(), -1);
  std::vector<Cell> best, current;
  int id = 0;
  for (const Cell& s : g.free_cells()) {
    if (comp[g.index(s)] >= 0) continue;
    current.clear();
    std::deque<Cell> q{s};
    comp[g.index(s)] = id;
    while (!q.empty()) {
      const Cell u = q.front();
      q.pop_front();
      current.push_back(u);
      for (const Cell& o : g.neighbour_offsets()) {
        const Cell v = u + o;
        if (g.is_free(v) && comp[g.index(v)] < 0) {
          comp[g.index(v)] = id;
          q.push_back(v);
        }
      }
    }
    if (current.size() > best.size()) best = current;
    ++id;
  }
  std::sort(best.begin(), best.end());
  return best;
}

// Walked length of visiting `points` in `order` from `start` (path distances via the planner).
double walked(const sdk::Planner& p, const sdk::Geometry& g, Cell start,
              const std::vector<Cell>& points, const std::vector<int>& order) {
  double total = 0;
  Cell at = start;
  for (int i : order) {
    const sdk::Area goal{points[i]};
    const auto r = p.plan(g, {at, &goal, nullptr}, sdk::StopCondition{});
    if (r.status != sdk::PlanStatus::found) continue;
    total += static_cast<double>(r.path.size());
    at = points[i];
  }
  return total;
}

// The original's tour: Christofides over straight-line distances (walls and robot ignored) from
// an arbitrary point; the robot walks to that point and then along the cycle. Mean over `starts`
// seeded arbitrary starting points.
double straight_line_baseline(const sdk::Planner& p, const sdk::Geometry& g, Cell robot,
                              const std::vector<Cell>& points, int starts, std::uint32_t seed) {
  plugins::astar::DistanceMatrix m;
  m.n = static_cast<int>(points.size());
  m.d.resize(static_cast<std::size_t>(m.n) * m.n);
  for (int a = 0; a < m.n; ++a)
    for (int b = 0; b < m.n; ++b)
      m.d[static_cast<std::size_t>(a) * m.n + b] =
          std::hypot(points[a].x - points[b].x, points[a].y - points[b].y);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, m.n - 1);
  double sum = 0;
  for (int k = 0; k < starts; ++k)
    sum += walked(p, g, robot, points, plugins::astar::christofides_cycle(m, pick(rng)));
  return sum / starts;
}

struct TourFigures {
  double ms;
  double length;
  double baseline;
};

TourFigures tour_figures(const sdk::Planner& p, const sdk::Geometry& g, Cell robot,
                         const std::vector<Cell>& points, int runs, int baseline_starts) {
  std::vector<double> times;
  sdk::TourResult t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = start_clock();
    t = p.tour(g, robot, points, sdk::StopCondition{});
    times.push_back(ms_since(t0));
  }
  return {median(times), t.length, straight_line_baseline(p, g, robot, points, baseline_starts, 7)};
}

void print_tour(const char* what, std::size_t n, const TourFigures& f) {
  std::printf("%-34s %5zu pts  %9.2f ms  length %8.0f  baseline %9.1f  (%+.1f%%)\n", what, n, f.ms,
              f.length, f.baseline, 100.0 * (f.length - f.baseline) / f.baseline);
}

}  // namespace

int main() {
  auto planner = testsupport::load_plugin<sdk::Planner>("astar");
  auto manhattan = testsupport::load_plugin<sdk::Planner>(
      "astar", sdk::Params({{"heuristic", std::string("manhattan")}}));
  auto plain = testsupport::load_plugin<sdk::Planner>(
      "astar", sdk::Params({{"two_opt", false}, {"or_opt", false}}));
  constexpr int kRuns = 7;

  // Visits on a random 1024 x 1024 grid, 30% walls.
  const auto big = random_grid(1024, 0.3, 42);
  const auto reachable = largest_component(*big);
  std::mt19937 rng(1);
  std::uniform_int_distribution<std::size_t> pick(0, reachable.size() - 1);
  std::vector<double> to_cell, to_cell_astar, to_set;
  std::uint64_t exp_cell = 0, exp_cell_astar = 0, exp_set = 0;
  for (int r = 0; r < kRuns; ++r) {
    Cell s = reachable[pick(rng)], t = reachable[pick(rng)];
    while (std::abs(s.x - t.x) + std::abs(s.y - t.y) < 1000) t = reachable[pick(rng)];
    const sdk::Area goal{t};
    auto t0 = start_clock();
    auto res = planner->plan(*big, {s, &goal, nullptr}, sdk::StopCondition{});
    to_cell.push_back(ms_since(t0));
    exp_cell = std::max(exp_cell, res.expansions);
    if (res.status != sdk::PlanStatus::found) std::printf("unexpected: no path\n");
    const std::size_t bfs_length = res.path.size();
    t0 = start_clock();
    res = manhattan->plan(*big, {s, &goal, nullptr}, sdk::StopCondition{});
    to_cell_astar.push_back(ms_since(t0));
    exp_cell_astar = std::max(exp_cell_astar, res.expansions);
    if (res.path.size() != bfs_length) std::printf("unexpected: A* path length differs\n");
    sdk::Area set;
    for (int k = 0; k < 64; ++k) set.push_back(reachable[pick(rng)]);
    sdk::areas::normalize(set);
    t0 = start_clock();
    res = planner->plan(*big, {s, &set, nullptr}, sdk::StopCondition{});
    to_set.push_back(ms_since(t0));
    exp_set = std::max(exp_set, res.expansions);
  }
  std::printf(
      "CPU times of the benchmark thread (medians)\n\n1024x1024, 30%% walls, %zu reachable cells, "
      "%d runs\n",
      reachable.size(), kRuns);
  std::printf("%-34s %9.2f ms  (max %.2f ms, up to %llu expansions)\n", "visit a far cell",
              median(to_cell), *std::max_element(to_cell.begin(), to_cell.end()),
              static_cast<unsigned long long>(exp_cell));
  std::printf("%-34s %9.2f ms  (max %.2f ms, up to %llu expansions)\n",
              "visit a far cell, heuristic=manhattan", median(to_cell_astar),
              *std::max_element(to_cell_astar.begin(), to_cell_astar.end()),
              static_cast<unsigned long long>(exp_cell_astar));
  std::printf("%-34s %9.2f ms  (max %.2f ms, up to %llu expansions)\n",
              "visit the nearest of 64 cells", median(to_set),
              *std::max_element(to_set.begin(), to_set.end()),
              static_cast<unsigned long long>(exp_set));

  // Tours over random points of the reachable region of a 256 x 256 grid, 30% walls.
  const auto mid = random_grid(256, 0.3, 43);
  const auto mid_reachable = largest_component(*mid);
  std::printf(
      "\ntours on a 256x256 grid, 30%% walls (times: medians; baseline: mean of "
      "arbitrary starts)\n");
  for (std::size_t n : {10u, 100u, 1000u}) {
    std::mt19937 prng(static_cast<std::uint32_t>(n));
    std::uniform_int_distribution<std::size_t> pp(0, mid_reachable.size() - 1);
    std::vector<Cell> pts;
    for (std::size_t k = 0; k < n; ++k) pts.push_back(mid_reachable[pp(prng)]);
    const Cell robot = mid_reachable[pp(prng)];
    print_tour("foreach point (random points)", n,
               tour_figures(*planner, *mid, robot, pts, n >= 1000 ? 5 : kRuns, n >= 1000 ? 3 : 10));
    print_tour("  same, Christofides only", n,
               tour_figures(*plain, *mid, robot, pts, n >= 1000 ? 5 : kRuns, 1));
  }

  // Rooms: the reachable cells of a square window of the 1024 x 1024 grid, the robot a few cells
  // outside it (what `foreach point in room` does on a large map).
  std::printf("\nrooms (square windows) of the 1024x1024 grid\n");
  for (int side : {4, 12, 38}) {
    const Cell lo{500, 500, 0}, hi{500 + side - 1, 500 + side - 1, 0};
    std::vector<Cell> pts;
    for (const Cell& c : reachable)
      if (c.x >= lo.x && c.x <= hi.x && c.y >= lo.y && c.y <= hi.y) pts.push_back(c);
    Cell robot = reachable[pick(rng)];
    for (const Cell& c : reachable)
      if (c.x >= lo.x - 8 && c.x < lo.x - 4 && c.y >= lo.y && c.y <= hi.y) robot = c;
    const std::string what =
        "foreach point in a " + std::to_string(side) + "x" + std::to_string(side) + " room";
    print_tour(what.c_str(), pts.size(), tour_figures(*planner, *big, robot, pts, kRuns, 5));
  }

  // The study map (core-language §10), robot at (2,4).
  const auto world =
      testsupport::load_plugin<sdk::World>("grid2d")->load(testsupport::study_world_json(), ".");
  std::printf("\nstudy map, robot at (2,4) (baseline: mean of 50 arbitrary starts)\n");
  for (const auto& [name, area] : *world.rooms) {
    const std::vector<Cell> pts(area.begin(), area.end());
    print_tour(("foreach point in " + name).c_str(), pts.size(),
               tour_figures(*planner, *world.geometry, world.robot, pts, kRuns, 50));
  }
  const auto& all = world.geometry->free_cells();
  print_tour("foreach point in world", all.size(),
             tour_figures(*planner, *world.geometry, world.robot,
                          std::vector<Cell>(all.begin(), all.end()), kRuns, 50));
  return 0;
}
