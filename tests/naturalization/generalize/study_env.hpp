#pragma once
// The study map of the 2018 user studies (docs/core-language.md §10) and what the generalization
// tests need around it: the grid2d world, the astar planner, the kernel executor and the rewriter.
#include <memory>
#include <string>

#include "flipper/kernel/executor.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

namespace flipper::testsupport {

inline const char* kStudyMap =
    R"JSON({"walls":[[-1,-1],[-1,0],[-1,1],[-1,2],[-1,3],[-1,4],[-1,5],[-1,6],[-1,7],[-1,8],[-1,9],[0,-1],[0,6],[0,9],[1,-1],[1,6],[1,9],[2,-1],[2,2],[2,6],[2,9],[3,-1],[3,2],[3,6],[3,9],[4,-1],[4,2],[4,6],[4,9],[5,-1],[5,2],[5,9],[6,-1],[6,2],[6,6],[6,7],[6,8],[6,9],[7,-1],[7,2],[7,6],[7,9],[8,-1],[8,1],[8,2],[8,3],[8,6],[8,9],[9,-1],[9,3],[9,9],[10,-1],[10,3],[10,6],[10,9],[11,-1],[11,3],[11,6],[11,9],[12,-1],[12,0],[12,1],[12,2],[12,3],[12,4],[12,5],[12,6],[12,7],[12,8],[12,9]],"items":[{"x":3,"y":8,"color":"blue","shape":"circle"},{"x":3,"y":8,"color":"yellow","shape":"square"},{"x":10,"y":8,"color":"green","shape":"triangle"},{"x":10,"y":8,"color":"red","shape":"triangle"},{"x":7,"y":4,"color":"red","shape":"circle"},{"x":7,"y":4,"color":"blue","shape":"circle"},{"x":7,"y":4,"color":"green","shape":"square"},{"x":7,"y":4,"color":"green","shape":"circle"},{"x":11,"y":1,"color":"blue","shape":"square"},{"x":4,"y":0,"color":"red","shape":"triangle"},{"x":4,"y":0,"color":"yellow","shape":"triangle"}],"robot":{"x":2,"y":4,"holding":[]},"rooms":{"room1":[[9,0],[9,1],[9,2],[10,0],[10,1],[10,2],[11,0],[11,1],[11,2]],"room2":[[0,0],[0,1],[1,0],[1,1],[2,0],[2,1],[3,0],[3,1],[4,0],[4,1],[5,0],[5,1],[6,0],[6,1],[7,0],[7,1]],"room3":[[0,3],[0,4],[0,5],[1,3],[1,4],[1,5],[2,3],[2,4],[2,5],[3,3],[3,4],[3,5],[4,3],[4,4],[4,5],[5,3],[5,4],[5,5],[6,3],[6,4],[6,5],[7,3],[7,4],[7,5],[8,4],[8,5],[9,4],[9,5],[10,4],[10,5],[11,4],[11,5]],"room4":[[0,7],[0,8],[1,7],[1,8],[2,7],[2,8],[3,7],[3,8],[4,7],[4,8],[5,7],[5,8]],"room5":[[7,7],[7,8],[8,7],[8,8],[9,7],[9,8],[10,7],[10,8],[11,7],[11,8]]},"bounds":{"min":[-1,-1],"max":[12,9]}}
)JSON";

struct StudyEnv {
  std::shared_ptr<sdk::World> world_plugin = load_plugin<sdk::World>("grid2d");
  std::shared_ptr<sdk::Planner> planner = load_plugin<sdk::Planner>("astar");
  kernel::Executor exec{planner};
  std::shared_ptr<sdk::Rewriter> rewriter = load_plugin<sdk::Rewriter>("rewrites");
  sdk::WorldState world = world_plugin->load(kStudyMap, ".");

  /// The study map with the robot at `robot`.
  sdk::WorldState at(sdk::Cell robot) const {
    sdk::WorldState w = world;
    w.robot = robot;
    return w;
  }
  /// Adds a lying item (with a fresh id) to `w`.
  static void add_item(sdk::WorldState& w, sdk::Cell at, const std::string& color,
                       const std::string& shape) {
    w.items.push_back({{w.next_item_id++, color, shape}, at});
  }
};

/// A program from canonical text.
inline sdk::Program P(const std::string& text) {
  return sdk::read_canonical(text);
}

}  // namespace flipper::testsupport
