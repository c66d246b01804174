#pragma once
// Shared helpers of the astar tests: the planner and world plugins, the study map, open grids.
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"
#include "study_world.hpp"

namespace flipper::testsupport {

inline std::shared_ptr<sdk::Planner> astar(const sdk::Params& p = {}) {
  return load_plugin<sdk::Planner>("astar", p);
}

inline const sdk::WorldState& study_map() {
  static const sdk::WorldState s = load_plugin<sdk::World>("grid2d")->load(study_world_json(), ".");
  return s;
}

/// A grid world from rows of text, top row first ('#' wall, anything else free); (0,0) is the
/// bottom-left character.
inline std::shared_ptr<const sdk::Geometry> grid_from_rows(const std::vector<std::string>& rows) {
  const int h = static_cast<int>(rows.size()), w = static_cast<int>(rows.front().size());
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      mask[static_cast<std::size_t>(x + w * y)] = rows[h - 1 - y][x] == '#' ? 0 : 1;
  return std::make_shared<const sdk::Geometry>(
      2, sdk::Cell{0, 0, 0}, sdk::Cell{w - 1, h - 1, 0}, std::move(mask),
      std::vector<sdk::Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, sdk::Cell>>{});
}

}  // namespace flipper::testsupport
