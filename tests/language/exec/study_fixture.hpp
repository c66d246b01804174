#pragma once
// Executor tests on the 2018 study map (configs/worlds/study2018.json) with the grid2d world and
// astar planner plugins, loaded straight from the build tree.
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "flipper/kernel/executor.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/world.hpp"
#include "plugin_fixture.hpp"

namespace flipper::testsupport {

inline nlohmann::json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return nlohmann::json::parse(in);
}

struct Study {
  std::shared_ptr<sdk::World> world = load_plugin<sdk::World>("grid2d");
  std::shared_ptr<sdk::Planner> planner = load_plugin<sdk::Planner>("astar");
  nlohmann::json doc =
      read_json_file(std::string(FLIPPER_SOURCE_DIR) + "/configs/worlds/study2018.json");

  /// The study world with the robot at (x, y) holding items given as (colour, shape) pairs.
  sdk::WorldState state(
      int x = 2, int y = 4,
      const std::vector<std::pair<std::string, std::string>>& holding = {}) const {
    nlohmann::json d = doc;
    d["robot"]["x"] = x;
    d["robot"]["y"] = y;
    d["robot"]["holding"] = nlohmann::json::array();
    for (const auto& [c, s] : holding)
      d["robot"]["holding"].push_back({{"color", c}, {"shape", s}});
    return world->load(d.dump(), ".");
  }
  sdk::Outcome run(const std::string& canonical, const sdk::WorldState& s,
                   kernel::ExecLimits limits = {}) const {
    kernel::Executor exec(planner, limits);
    return exec.run(sdk::read_canonical(canonical), s);
  }
};

/// "m(3,4)" / "p(7,4)red circle" / "d(2,4)blue square" per step, space separated.
inline std::string trace_text(const std::vector<sdk::TraceStep>& trace) {
  std::ostringstream o;
  for (const auto& s : trace) {
    if (o.tellp() > 0) o << ' ';
    const char* a = s.act == sdk::TraceStep::Act::move   ? "m"
                    : s.act == sdk::TraceStep::Act::pick ? "p"
                                                         : "d";
    o << a << '(' << s.cell.x << ',' << s.cell.y << ')';
    if (s.act != sdk::TraceStep::Act::move) o << s.item.color << ' ' << s.item.shape;
  }
  return o.str();
}

/// Items lying on a cell, as "colour shape" in world order.
inline std::vector<std::string> items_at(const sdk::WorldState& s, int x, int y) {
  std::vector<std::string> out;
  for (const auto& li : s.items)
    if (li.at.x == x && li.at.y == y) out.push_back(li.item.color + " " + li.item.shape);
  return out;
}

}  // namespace flipper::testsupport
