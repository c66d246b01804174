// grid2d: the world plugin for the 2-D grid worlds of the user studies (walls on integer cells).
// It reads and writes the protocol's world object through the SDK's world_format helpers; this
// file only adds what is specific to a grid: walls, the free mask and the 4-neighbourhood.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"
#include "flipper/sdk/world_format.hpp"

namespace flipper::plugins::grid2d {
namespace {

namespace sdk = flipper::sdk;
namespace wf = flipper::sdk::world_format;

// Tie order of shortest paths (core-language §8): right, left, up, down.
const std::vector<sdk::Cell> kNeighbours = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};

std::vector<std::pair<std::string, sdk::Cell>> directions() {
  return {{"up", {0, 1, 0}}, {"down", {0, -1, 0}}, {"left", {-1, 0, 0}}, {"right", {1, 0, 0}}};
}

class Grid2dWorld final : public sdk::World {
 public:
  explicit Grid2dWorld(const sdk::Params&) {}
  static sdk::ParamSchema schema() { return {}; }

 protected:
  sdk::WorldState do_load(std::string_view text, const std::string&,
                          const sdk::WorldLimits& limits) const override {
    wf::WorldDocument doc = wf::parse_world(text, 2);
    if (doc.octomap)
      throw sdk::Error(sdk::codes::kBadWorld,
                       "octomap: grid2d worlds list their walls; use a 3-D world plugin");
    const wf::Bounds box = wf::effective_bounds(doc);
    // A 110-byte world can name a box of 16382^2 cells: refused before the mask is allocated.
    wf::check_cells(wf::cell_count(box), limits);
    const auto sx = static_cast<std::uint64_t>(std::int64_t{box.max.x} - box.min.x + 1);
    const auto sy = static_cast<std::uint64_t>(std::int64_t{box.max.y} - box.min.y + 1);
    std::vector<std::uint8_t> mask(sx * sy, 1);
    for (const sdk::Cell& w : doc.walls) {
      if (w.x < box.min.x || w.x > box.max.x || w.y < box.min.y || w.y > box.max.y)
        continue;  // reported by check_placement with the point's name
      mask[static_cast<std::size_t>(w.x - box.min.x) +
           sx * static_cast<std::size_t>(w.y - box.min.y)] = 0;
    }
    auto geometry = std::make_shared<const sdk::Geometry>(2, box.min, box.max, std::move(mask),
                                                          kNeighbours, directions());
    wf::check_placement(doc, *geometry);
    return wf::make_state(std::move(doc), std::move(geometry));
  }

  std::string do_save(const sdk::WorldState& state) const override {
    if (!state.geometry || state.geometry->dims() != 2)
      throw sdk::Error(sdk::codes::kInternal, "grid2d: cannot save a world that is not 2-D");
    const sdk::Geometry& g = *state.geometry;
    // Walls are the blocked cells of the box, listed in (x, y) order.
    std::vector<sdk::Cell> walls;
    for (std::int32_t x = g.min().x; x <= g.max().x; ++x)
      for (std::int32_t y = g.min().y; y <= g.max().y; ++y)
        if (!g.is_free({x, y, 0})) walls.push_back({x, y, 0});
    return wf::write_world(state, {{"walls", wf::points_json(walls, 2)}});
  }

  int do_dims() const override { return 2; }
};

}  // namespace
}  // namespace flipper::plugins::grid2d

FLIPPER_PLUGIN(flipper::plugins::grid2d::Grid2dWorld, world, "grid2d", FLIPPER_PLUGIN_VERSION,
               "2-D grid world: walls on integer cells, 4-neighbourhood (right, left, up, down)")
