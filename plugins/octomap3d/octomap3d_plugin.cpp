// The octomap3d world plugin: 3-D points [x, y, z], obstacles in an OctoMap octree, free cells
// decided by FCL (the robot body placed at the cell centre must not touch occupied space).
//
// Neighbour offsets (the tie order of shortest paths): +x, -x, +y, -y, +z, -z, i.e. the 2-D order
// right, left, up, down followed by ascend, descend.
// Directions: `up`/`down` = +/-y and `left`/`right` = -/+x exactly as in 2-D (the plan view, so 2-D
// habits and programs carry over floor by floor), plus `ascend`/`descend` = +/-z. The kernel
// gives the grammar these six words (unless `grammar.directions` narrows them).
#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/world.hpp"
#include "obstacles.hpp"
#include "occupancy.hpp"

namespace flipper::plugins::octomap3d {

namespace {

namespace param = sdk::param;

constexpr param::Double kResolution{
    "resolution", 1.0, 1e-3, 1e3,
    "edge of one cell (and of the octree voxels built from boxes), metres"};
constexpr param::Choice<Body::Shape, 2> kBody{
    "body", Body::Shape::box, {"box", "sphere"}, "robot body shape used for collision checks"};
constexpr param::Double kBodySize{"body_size", 0.5, 1e-3, 1e3,
                                  "robot body: box edge or sphere diameter, metres"};
constexpr param::Int<std::uint64_t> kMaxFileBytes{
    "max_file_bytes", 268435456, 1, std::uint64_t{1} << 40,
    "largest .bt file read (regular files only): file_too_large / not_a_regular_file"};

}  // namespace

class OctomapWorld final : public sdk::World {
 public:
  explicit OctomapWorld(const sdk::Params& p)
      : resolution_(param::get(p, kResolution)),
        max_file_bytes_(param::get(p, kMaxFileBytes)),
        body_{param::get(p, kBody), param::get(p, kBodySize)} {}

  static sdk::ParamSchema schema() {
    return param::schema(kResolution, kBody, kBodySize, kMaxFileBytes);
  }

 protected:
  sdk::WorldState do_load(std::string_view world_json, const std::string& base_dir,
                          const sdk::WorldLimits& limits) const override {
    wf::WorldDocument doc = wf::parse_world(world_json, 3);
    // The box the text names (explicit or default) first: a few bytes can name billions of cells.
    wf::check_cells(wf::cell_count(wf::effective_bounds(doc)), limits);
    Obstacles obstacles = take_obstacles(doc);
    // The smaller of this plugin's max_file_bytes and the host's limit, named in the refusal.
    const FileLimit file_limit = limits.max_file_bytes < max_file_bytes_
                                     ? FileLimit{limits.max_file_bytes, "input.max_file_bytes"}
                                     : FileLimit{max_file_bytes_, "max_file_bytes"};
    auto tree = build_octree(obstacles, base_dir, resolution_, file_limit);

    CellBox bounds;
    if (doc.bounds) {
      bounds = {doc.bounds->min, doc.bounds->max};
    } else {  // the protocol's default box, grown by the obstacles only this plugin knows of
      const wf::Bounds b = wf::default_bounds(doc);
      bounds = {b.min, b.max};
      for (const CellBox& box : obstacles.boxes) grow(bounds, box);
      CellBox occupied;
      if (occupied_cell_box(*tree, resolution_, occupied)) grow(bounds, occupied);
    }
    const std::uint64_t cells = std::uint64_t(bounds.max.x - bounds.min.x + 1) *
                                std::uint64_t(bounds.max.y - bounds.min.y + 1) *
                                std::uint64_t(bounds.max.z - bounds.min.z + 1);
    if (cells > kMaxCells)
      throw sdk::Error(sdk::codes::kBadWorld, "bounds: " + std::to_string(cells) +
                                                  " cells is larger than the limit of " +
                                                  std::to_string(kMaxCells));
    wf::check_cells(cells, limits);  // grown by the obstacles: checked before FCL fills the mask

    auto space = std::make_shared<const FclSpace>(std::move(tree), body_, resolution_, bounds,
                                                  std::move(obstacles));
    auto geometry = std::make_shared<const sdk::Geometry>(
        3, bounds.min, bounds.max, space->free_mask(), neighbour_offsets(), directions(), space);
    if (geometry->in_bounds(doc.robot) && !geometry->is_free(doc.robot))
      throw sdk::Error(sdk::codes::kBadWorld,
                       "robot " + wf::describe(doc.robot, 3) +
                           " collides with occupied space (body: " + body_name() + ")");
    wf::check_placement(doc, *geometry);
    return wf::make_state(std::move(doc), std::move(geometry));
  }

  std::string do_save(const sdk::WorldState& state) const override {
    if (!state.geometry || state.geometry->dims() != 3)
      throw sdk::Error(sdk::codes::kInternal, "octomap3d: cannot save a world that is not 3-D");
    const sdk::Geometry& g = *state.geometry;
    if (const auto* space = dynamic_cast<const FclSpace*>(g.continuous()))
      return wf::write_world(state, obstacle_fields(space->obstacles()));
    // A geometry built elsewhere: its blocked cells become walls.
    Obstacles walls;
    for (std::size_t i = 0; i < g.cell_count(); ++i)
      if (!g.free_mask()[i]) walls.walls.push_back(g.cell_at(i));
    sdk::areas::normalize(walls.walls);
    return wf::write_world(state, obstacle_fields(walls));
  }

  int do_dims() const override { return 3; }

 private:
  static constexpr std::uint64_t kMaxCells = 8'000'000;

  static void grow(CellBox& b, const CellBox& o) {
    b.min = {std::min(b.min.x, o.min.x), std::min(b.min.y, o.min.y), std::min(b.min.z, o.min.z)};
    b.max = {std::max(b.max.x, o.max.x), std::max(b.max.y, o.max.y), std::max(b.max.z, o.max.z)};
  }

  static std::vector<sdk::Cell> neighbour_offsets() {
    return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  }
  static std::vector<std::pair<std::string, sdk::Cell>> directions() {
    return {{"up", {0, 1, 0}},    {"down", {0, -1, 0}},  {"left", {-1, 0, 0}},
            {"right", {1, 0, 0}}, {"ascend", {0, 0, 1}}, {"descend", {0, 0, -1}}};
  }
  std::string body_name() const {
    return std::string(body_.shape == Body::Shape::box ? "box " : "sphere ") +
           nlohmann::json(body_.size).dump();
  }

  const double resolution_;
  const std::uint64_t max_file_bytes_;
  const Body body_;
};

}  // namespace flipper::plugins::octomap3d

FLIPPER_PLUGIN(
    flipper::plugins::octomap3d::OctomapWorld, world, "octomap3d", FLIPPER_PLUGIN_VERSION,
    "3-D world: OctoMap octree obstacles (.bt or boxes), FCL body collision, 6-neighbourhood")
