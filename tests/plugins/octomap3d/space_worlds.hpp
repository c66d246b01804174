#pragma once
// Shared by the octomap3d, ompl and swap tests: the 3-D two-floor world of configs/worlds and the
// plugins that load it.
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

namespace flipper::testsupport {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string worlds_dir() {
  return std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds";
}

/// configs/worlds/two-floors.json: floors z = 0 and z = 2, a slab at z = 1 open at the shaft
/// (8,1,1); floor 0 split by the wall x = 4 (door (4,3,0)) into room1 | room2, floor 1 split by
/// the wall y = 4 (door (2,4,2)) into room3 (south) | room4 (north). Robot at (1,1,0).
inline std::string two_floors_json() {
  return read_text(worlds_dir() + "/two-floors.json");
}

inline std::shared_ptr<sdk::World> octomap_world(const sdk::Params& p = {}) {
  return load_plugin<sdk::World>("octomap3d", p);
}

inline sdk::WorldState two_floors(const sdk::Params& p = {}) {
  return octomap_world(p)->load(two_floors_json(), worlds_dir());
}

}  // namespace flipper::testsupport
