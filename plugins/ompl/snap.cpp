#include "snap.hpp"

#include <cmath>
#include <cstdlib>
#include <unordered_map>

namespace flipper::plugins::ompl {

using sdk::Cell;

namespace {

bool neighbours(Cell a, Cell b) {
  return std::abs(a.x - b.x) + std::abs(a.y - b.y) + std::abs(a.z - b.z) == 1;
}

Cell round_cell(const Waypoint& p) {
  return {static_cast<std::int32_t>(std::lround(p[0])),
          static_cast<std::int32_t>(std::lround(p[1])),
          static_cast<std::int32_t>(std::lround(p[2]))};
}

// Cuts every loop: when a cell is entered again, everything since its earlier visit goes.
// Positions are keyed by dense cell index; entries left behind by a cut are recognised as stale
// because the cell at the stored position differs.
void remove_loops(const sdk::Geometry& g, Cell start, std::vector<Cell>& path) {
  std::unordered_map<std::size_t, std::size_t> at;  // cell index -> position in `out` + 1
  at[g.index(start)] = 0;
  std::vector<Cell> out;
  out.reserve(path.size());
  for (const Cell& c : path) {
    auto it = at.find(g.index(c));
    const bool seen =
        it != at.end() &&
        (it->second == 0 ? c == start : it->second <= out.size() && out[it->second - 1] == c);
    if (seen) {
      out.resize(it->second);  // back to the earlier visit of c
      continue;
    }
    out.push_back(c);
    at[g.index(c)] = out.size();
  }
  path.swap(out);
}

}  // namespace

bool snap_path(const std::vector<Waypoint>& waypoints, Cell goal, CellSearch& search,
               std::vector<Cell>& path) {
  path.clear();
  Cell cur = search.start();
  auto advance = [&](Cell anchor) {
    if (anchor == cur || !search.passable(anchor)) return;
    if (neighbours(cur, anchor)) {
      path.push_back(anchor);
      cur = anchor;
    } else if (search.connect(cur, anchor, /*margin=*/2, path)) {
      cur = anchor;
    }  // else: the line squeezed past something the grid cannot; skip this anchor
  };
  for (std::size_t s = 1; s < waypoints.size(); ++s) {
    const Waypoint& a = waypoints[s - 1];
    const Waypoint& b = waypoints[s];
    const double len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                 (b[2] - a[2]) * (b[2] - a[2]));
    const int steps = std::max(1, static_cast<int>(std::ceil(len * 8)));
    for (int i = 1; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      advance(round_cell(
          {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])}));
    }
  }
  if (cur != goal && !search.connect(cur, goal, /*margin=*/-1, path)) return false;
  remove_loops(search.geometry(), search.start(), path);
  return true;
}

}  // namespace flipper::plugins::ompl
