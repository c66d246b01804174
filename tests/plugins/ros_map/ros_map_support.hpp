#pragma once
// Test support for the ros_map world plugin: scratch map files (YAML + PGM) written per test,
// the plugin loaded with given params, and a breadth-first search written here (not the astar
// plugin's) as the independent oracle of path lengths.
#include <cstdint>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

namespace flipper::rosmaptest {

/// A fresh directory under build/tests/tmp/ros_map/<name>.
inline std::string scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "ros_map" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline std::string write(const std::string& dir, const std::string& file,
                         const std::string& bytes) {
  const std::string path = dir + "/" + file;
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  REQUIRE(out.good());
  return path;
}

/// A binary P5 image, rows from the top.
inline std::string p5(const std::vector<std::vector<int>>& rows) {
  std::string s =
      "P5\n" + std::to_string(rows[0].size()) + " " + std::to_string(rows.size()) + "\n255\n";
  for (const auto& r : rows)
    for (int v : r) s.push_back(static_cast<char>(v));
  return s;
}

/// A map_server YAML; `extra` lines are appended (mode, ...).
inline std::string map_yaml(const std::string& image, double resolution, const std::string& origin,
                            int negate, double occupied, double free_thresh,
                            const std::string& extra = "") {
  std::ostringstream s;
  s << "image: " << image << "\nresolution: " << resolution << "\norigin: " << origin
    << "\nnegate: " << negate << "\noccupied_thresh: " << occupied
    << "\nfree_thresh: " << free_thresh << "\n"
    << extra;
  return s.str();
}

inline std::shared_ptr<sdk::World> world(const sdk::Params& params = {}) {
  return testsupport::load_plugin<sdk::World>("ros_map", params);
}

inline sdk::Params params(double inflation_radius, bool inflate_unknown = false, int lethal = 100) {
  sdk::Params p;
  p.set("inflation_radius", inflation_radius);
  p.set("inflate_unknown", inflate_unknown);
  p.set("lethal_threshold", std::int64_t{lethal});
  return p;
}

/// Steps of a shortest 4-neighbour path from `start` to the nearest cell of `goals` on the free
/// mask, or -1.
inline long bfs_steps(const sdk::Geometry& g, sdk::Cell start, const sdk::Area& goals) {
  const std::size_t n = g.cell_count();
  std::vector<std::uint8_t> goal(n, 0);
  for (const auto& c : goals) goal[g.index(c)] = 1;
  std::vector<long> dist(n, -1);
  std::deque<sdk::Cell> queue{start};
  dist[g.index(start)] = 0;
  const sdk::Cell steps[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  while (!queue.empty()) {
    const sdk::Cell c = queue.front();
    queue.pop_front();
    if (goal[g.index(c)] != 0) return dist[g.index(c)];
    for (const auto& s : steps) {
      const sdk::Cell d{c.x + s.x, c.y + s.y, 0};
      if (!g.is_free(d) || dist[g.index(d)] >= 0) continue;
      dist[g.index(d)] = dist[g.index(c)] + 1;
      queue.push_back(d);
    }
  }
  return -1;
}

}  // namespace flipper::rosmaptest
