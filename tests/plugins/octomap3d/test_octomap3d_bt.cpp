// Worlds whose occupied space comes from an OctoMap .bt file, written here with the OctoMap
// library into a scratch directory (no binary file is kept in the repository).
#include <octomap/OcTree.h>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "flipper/sdk/errors.hpp"
#include "space_worlds.hpp"

using namespace flipper;
using sdk::Cell;

namespace {

struct ScratchDir {
  std::filesystem::path path;
  ScratchDir() {
    path = std::filesystem::temp_directory_path() /
           ("flipper-octomap3d-" + std::to_string(::getpid()) + "-" +
            std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() { std::filesystem::remove_all(path); }
};

// A wall x = 3 (cells y 0..4, z 0) as voxels of a tree at `res`.
void write_wall(const std::filesystem::path& file, double res) {
  octomap::OcTree tree(res);
  for (double y = 0; y < 5; y += res)
    for (double z = 0; z < 1; z += res)
      for (double x = 3; x < 4; x += res)
        tree.updateNode(
            octomap::point3d(float(x + res / 2), float(y + res / 2), float(z + res / 2)), true);
  tree.updateInnerOccupancy();
  REQUIRE(tree.writeBinary(file.string()));
}

const char* kWorld = R"({"octomap": "wall.bt", "bounds": {"min": [0, 0, 0], "max": [6, 4, 0]},
                         "robot": {"x": 1, "y": 1, "z": 0}})";

}  // namespace

TEST_CASE("octomap3d: occupied space from a .bt file next to the world file", "[octomap3d][bt]") {
  ScratchDir dir;
  write_wall(dir.path / "wall.bt", 1.0);
  auto world = testsupport::octomap_world();
  const sdk::WorldState s = world->load(kWorld, dir.path.string());
  for (int y = 0; y <= 4; ++y) {
    REQUIRE(!s.geometry->is_free({3, y, 0}));
    REQUIRE(s.geometry->is_free({2, y, 0}));
    REQUIRE(s.geometry->is_free({4, y, 0}));
  }
  REQUIRE(s.geometry->free_cells().size() == 35 - 5);
  // save keeps the file reference, not the voxels
  const std::string saved = world->save(s);
  REQUIRE(saved.find("\"octomap\":\"wall.bt\"") != std::string::npos);
  REQUIRE(world->load(saved, dir.path.string()).geometry->free_mask() == s.geometry->free_mask());
}

TEST_CASE("octomap3d: a finer .bt tree is discretised at the plugin resolution",
          "[octomap3d][bt]") {
  ScratchDir dir;
  write_wall(dir.path / "wall.bt", 0.25);
  const sdk::WorldState s = testsupport::octomap_world()->load(kWorld, dir.path.string());
  REQUIRE(s.geometry->free_cells().size() == 35 - 5);
  REQUIRE(!s.geometry->is_free({3, 2, 0}));
}

TEST_CASE("octomap3d: default bounds include the .bt file's occupied voxels", "[octomap3d][bt]") {
  ScratchDir dir;
  write_wall(dir.path / "wall.bt", 1.0);
  const sdk::WorldState s = testsupport::octomap_world()->load(
      R"({"octomap": "wall.bt", "robot": {"x": 1, "y": 1, "z": 0}})", dir.path.string());
  REQUIRE(s.geometry->min() == Cell{1, 0, 0});
  REQUIRE(s.geometry->max() == Cell{3, 4, 0});
}

TEST_CASE("octomap3d: an unreadable .bt file is bad_world", "[octomap3d][bt]") {
  ScratchDir dir;
  std::ofstream(dir.path / "wall.bt") << "this is not an octree";
  try {
    (void)testsupport::octomap_world()->load(kWorld, dir.path.string());
    FAIL("accepted");
  } catch (const sdk::Error& e) {
    REQUIRE(e.code() == sdk::codes::kBadWorld);
    REQUIRE(std::string(e.what()).find("wall.bt") != std::string::npos);
  }
}
