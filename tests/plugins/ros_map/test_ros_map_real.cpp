// The two real Nav2 maps of data/ros-maps/ (NOTICE): cells against the images' own pixel
// counts, plans to each named region against a breadth-first search written in this test, and
// `flipper run` on the shipped configs.
#include <yaml-cpp/yaml.h>
#include <catch2/catch.hpp>
#include <map>

#include "cli_test_support.hpp"
#include "flipper/sdk/planner.hpp"
#include "ros_map_support.hpp"

using namespace flipper;
using namespace flipper::rosmaptest;
using sdk::Cell;

namespace {

const std::string kMaps = std::string(FLIPPER_SOURCE_DIR) + "/data/ros-maps";

std::string read(const std::string& path) {
  return clitest::read_file(path);
}

sdk::WorldState load_real(const std::string& name, double radius) {
  return world(params(radius))->load(read(kMaps + "/" + name + ".world.json"), kMaps);
}

std::shared_ptr<sdk::Planner> astar() {
  static auto p = testsupport::load_plugin<sdk::Planner>("astar");
  return p;
}

// For each room: the planner's path length, which must be the BFS's.
std::map<std::string, long> plan_steps(const sdk::WorldState& s) {
  std::map<std::string, long> steps;
  for (const auto& [room, area] : *s.rooms) {
    const auto r = astar()->plan(*s.geometry, {s.robot, &area, nullptr}, sdk::StopCondition{});
    REQUIRE(r.status == sdk::PlanStatus::found);
    REQUIRE(sdk::areas::contains(area, r.target));
    // Every step is one 4-neighbour move onto a free cell.
    Cell at = s.robot;
    for (const Cell& c : r.path) {
      REQUIRE(std::abs(c.x - at.x) + std::abs(c.y - at.y) == 1);
      REQUIRE(s.geometry->is_free(c));
      at = c;
    }
    const long bfs = bfs_steps(*s.geometry, s.robot, area);
    INFO(room);
    REQUIRE(static_cast<long>(r.path.size()) == bfs);
    steps[room] = bfs;
  }
  return steps;
}

}  // namespace

TEST_CASE("depot: 604 x 307 cells, grey 205 is free at free_thresh 0.25", "[ros_map][real]") {
  // The image's histogram: 170587 pixels of 254, 8894 of 205, 5947 of 0. With
  // occupied_thresh 0.65 and free_thresh 0.25: 254 -> p 0.004 free, 205 -> p 0.196 free,
  // 0 -> p 1 occupied.
  const auto s = load_real("depot", 0);
  REQUIRE(s.geometry->max() == Cell{603, 306, 0});
  REQUIRE(s.geometry->free_cells().size() == 170587 + 8894);
  REQUIRE(s.robot == Cell{40, 150, 0});  // (2.0 m, 7.5 m) at 0.05 m from (0, 0)
  REQUIRE(s.rooms->size() == 4);
  REQUIRE(s.items.size() == 3);
}

TEST_CASE("tb3_sandbox: grey 205 is unknown at free_thresh 0.196", "[ros_map][real]") {
  // 7903 pixels of 254, 138683 of 205, 870 of 0; 205 -> p = 50/255 = 0.19608, not below 0.196.
  const auto s = load_real("tb3_sandbox", 0);
  REQUIRE(s.geometry->max() == Cell{383, 383, 0});
  REQUIRE(s.geometry->free_cells().size() == 7903);
  REQUIRE(s.robot == Cell{160, 190, 0});  // (-2.0 m, -0.5 m) from (-10 m, -10 m) at 0.05 m
}

TEST_CASE("depot: a plan to each region, as long as an independent BFS", "[ros_map][real]") {
  const auto s = load_real("depot", 0.2);
  const auto steps = plan_steps(s);
  // Recorded from the BFS above (the planner agrees with it room by room).
  REQUIRE(steps == std::map<std::string, long>{
                       {"room1", 51}, {"room2", 60}, {"room3", 320}, {"room4", 470}});
}

TEST_CASE("tb3_sandbox: a plan to each region, as long as an independent BFS", "[ros_map][real]") {
  const auto s = load_real("tb3_sandbox", 0.105);
  const auto steps = plan_steps(s);
  // Recorded from the BFS above (the planner agrees with it room by room).
  REQUIRE(steps ==
          std::map<std::string, long>{{"room5", 2}, {"room6", 74}, {"room7", 70}, {"room8", 51}});
}

TEST_CASE("the ROS-map grammar is the core grammar plus the region names", "[ros_map][real]") {
  const std::string core = read(std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/core.grammar");
  const std::string ros =
      read(std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/ros-maps.grammar");
  REQUIRE(ros.compare(0, core.size(), core) == 0);
}

TEST_CASE("flipper run plans on the real maps by region name", "[ros_map][real][cli]") {
  const auto depot = clitest::run_flipper("run --config configs/ros-map-depot.yaml \"visit yard\"");
  INFO(depot.out);
  REQUIRE(depot.status == 0);
  REQUIRE(clitest::contains(depot.out, "interpretation: {visit room4}"));
  REQUIRE(clitest::contains(depot.out, "realizable: yes"));
  const auto tb3 = clitest::run_flipper("run --config configs/ros-map-tb3.yaml \"visit east\"");
  INFO(tb3.out);
  REQUIRE(tb3.status == 0);
  REQUIRE(clitest::contains(tb3.out, "interpretation: {visit room6}"));
  // Metres out: cell (234, 190)'s centre is -10 + 234.5 * 0.05, -10 + 190.5 * 0.05.
  REQUIRE(clitest::contains(tb3.out, "robot: [234,190] (1.725 m, -0.475 m)"));
  REQUIRE(clitest::contains(tb3.out, "red circle@[211,211] (0.575 m, 0.575 m)"));
  REQUIRE(clitest::contains(tb3.out, "realizable: yes"));
}

TEST_CASE("each ROS-map config publishes plans in its map's metres", "[ros_map][real]") {
  // world.origin is the metres of cell (0, 0)'s centre: the map's origin + resolution / 2.
  for (const auto& [config, map] : std::vector<std::pair<std::string, std::string>>{
           {"ros-map-depot.yaml", "depot.yaml"}, {"ros-map-tb3.yaml", "tb3_sandbox.yaml"}}) {
    INFO(config);
    const YAML::Node c = YAML::LoadFile(std::string(FLIPPER_SOURCE_DIR) + "/configs/" + config);
    const YAML::Node m = YAML::LoadFile(kMaps + "/" + map);
    const double res = m["resolution"].as<double>();
    REQUIRE(c["world"]["resolution"].as<double>() == res);
    REQUIRE(c["world"]["origin"][0].as<double>() ==
            Approx(m["origin"][0].as<double>() + res / 2).margin(1e-12));
    REQUIRE(c["world"]["origin"][1].as<double>() ==
            Approx(m["origin"][1].as<double>() + res / 2).margin(1e-12));
    REQUIRE(c["world"]["plugin"].as<std::string>() == "ros_map");
  }
}
