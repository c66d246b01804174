// ros_map: a 2-D world whose cells come from a ROS map_server occupancy grid (YAML + PGM, read
// as Nav2 reads it) and whose rooms, items and robot start may be given in metres in the map
// frame (docs/ros-maps.md). The planners see the free-cell mask: free by value, not unknown,
// and farther than inflation_radius from every occupied cell (Nav2's inscribed radius).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bounded_file.hpp"
#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"
#include "flipper/sdk/world_format.hpp"
#include "map_yaml.hpp"
#include "occupancy.hpp"
#include "pgm.hpp"
#include "sidecar.hpp"

namespace flipper::plugins::ros_map {
namespace {

namespace sdk = flipper::sdk;
namespace wf = flipper::sdk::world_format;
namespace param = sdk::param;
using nlohmann::json;

constexpr param::Double kInflationRadius{
    "inflation_radius", 0.0, 0.0, 100.0,
    "robot radius, metres: cells whose centre lies within it of an occupied cell's centre are "
    "blocked (Nav2's inscribed radius)"};
constexpr param::Bool kInflateUnknown{"inflate_unknown", false,
                                      "unknown cells are inflated as occupied ones are (Nav2's "
                                      "inflation layer: inflate_unknown)"};
constexpr param::Int<int> kLethal{
    "lethal_threshold", 100, 1, 100,
    "occupancy value from which a cell is blocked (Nav2's static layer: lethal_cost_threshold); "
    "unknown cells are always blocked"};
constexpr param::Int<std::uint64_t> kMaxCells{
    "max_cells", 4194304, 1, 268435456,
    "largest map, in cells, refused from the PGM header before allocation (world_too_large)"};
constexpr param::Int<std::uint64_t> kMaxFileBytes{
    "max_file_bytes", 67108864, 1, std::uint64_t{1} << 40,
    "largest map YAML or PGM file read (regular files only): file_too_large"};

// The YAML of a map_server map is a few lines; anything larger is not one.
constexpr std::uint64_t kMaxYamlBytes = 1 << 20;

// Tie order of shortest paths as grid2d (core-language §8): right, left, up, down.
std::vector<sdk::Cell> neighbours() {
  return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
}
std::vector<std::pair<std::string, sdk::Cell>> directions() {
  return {{"up", {0, 1, 0}}, {"down", {0, -1, 0}}, {"left", {-1, 0, 0}}, {"right", {1, 0, 0}}};
}

// The map behind a geometry: its file (for save) and frame, and a continuous view of its free
// cells for sampling planners (cell units, the centre of cell (i, j) at (i, j)).
class MapSpace final : public sdk::ContinuousSpace {
 public:
  MapSpace(std::string yaml_path, MapFrame frame, std::vector<std::uint8_t> mask)
      : yaml_path_(std::move(yaml_path)), frame_(frame), mask_(std::move(mask)) {}

  bool is_state_valid(const double p[3]) const override {
    const double x = std::round(p[0]), y = std::round(p[1]);
    if (!(x >= 0 && x < frame_.width && y >= 0 && y < frame_.height)) return false;
    return mask_[static_cast<std::size_t>(x) + frame_.width * static_cast<std::size_t>(y)] != 0;
  }
  bool is_motion_valid(const double a[3], const double b[3]) const override {
    // Checked every tenth of a cell: no free cell is skipped between two samples.
    const double dx = b[0] - a[0], dy = b[1] - a[1];
    const int steps = static_cast<int>(std::ceil(std::hypot(dx, dy) * 10)) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const double p[3] = {a[0] + t * dx, a[1] + t * dy, 0};
      if (!is_state_valid(p)) return false;
    }
    return true;
  }
  const std::string& yaml_path() const { return yaml_path_; }
  const MapFrame& frame() const { return frame_; }

 private:
  std::string yaml_path_;
  MapFrame frame_;
  std::vector<std::uint8_t> mask_;
};

class RosMapWorld final : public sdk::World {
 public:
  explicit RosMapWorld(const sdk::Params& p)
      : inflation_radius_(param::get(p, kInflationRadius)),
        inflate_unknown_(param::get(p, kInflateUnknown)),
        lethal_(param::get(p, kLethal)),
        max_cells_(param::get(p, kMaxCells)),
        max_file_bytes_(param::get(p, kMaxFileBytes)) {}

  static sdk::ParamSchema schema() {
    return param::schema(kInflationRadius, kInflateUnknown, kLethal, kMaxCells, kMaxFileBytes);
  }

 protected:
  sdk::WorldState do_load(std::string_view text, const std::string& base_dir,
                          const sdk::WorldLimits& limits) const override {
    json world;
    try {
      world = json::parse(text);
    } catch (const json::exception& e) {
      throw sdk::Error(sdk::codes::kBadWorld, std::string("world: not valid JSON: ") + e.what());
    }
    if (!world.is_object())
      throw sdk::Error(sdk::codes::kBadWorld, "a world must be a JSON object");
    if (!world.contains("map")) {
      wf::parse_world(text, 2);  // the protocol's own complaints first (robot, items, rooms)
      throw sdk::Error(sdk::codes::kBadWorld,
                       "map: missing; a ros_map world names its map_server YAML "
                       "(\"map\": \"depot.yaml\", relative to the world file)");
    }
    if (!world["map"].is_string() || world["map"].get<std::string>().empty())
      throw sdk::Error(sdk::codes::kBadWorld, "map must be the path of a map_server YAML file");
    std::filesystem::path yaml_path(world["map"].get<std::string>());
    if (yaml_path.is_relative()) yaml_path = std::filesystem::path(base_dir) / yaml_path;
    // Absolute: a saved world names its map wherever it is loaded from.
    yaml_path = std::filesystem::absolute(yaml_path).lexically_normal();
    const std::string yaml_file = yaml_path.string();

    // This plugin's limits or the host's, whichever is smaller, named in the refusal.
    const bool host_bytes = limits.max_file_bytes < max_file_bytes_;
    const std::uint64_t max_bytes = host_bytes ? limits.max_file_bytes : max_file_bytes_;
    const char* bytes_name = host_bytes ? "input.max_file_bytes" : "max_file_bytes";
    const bool host_cells = limits.max_cells < max_cells_;
    const MapYaml map = parse_map_yaml(
        read_bounded_file(yaml_file, std::min(kMaxYamlBytes, max_bytes), "map", bytes_name),
        yaml_file);
    const GreyImage image = decode_pgm(
        read_bounded_file(map.image, max_bytes, "map image", bytes_name), map.image,
        host_cells ? limits.max_cells : max_cells_, host_cells ? "world.max_cells" : "max_cells");
    const OccupancyGrid grid = occupancy_grid(image, map);
    const MapFrame frame{map.resolution, map.origin_x, map.origin_y, grid.width, grid.height};
    std::vector<std::uint8_t> mask =
        free_mask(grid, lethal_, inflation_radius_ / map.resolution, inflate_unknown_);
    auto space = std::make_shared<const MapSpace>(yaml_file, frame, mask);
    const sdk::Cell lo{0, 0, 0};
    const sdk::Cell hi{static_cast<std::int32_t>(grid.width) - 1,
                       static_cast<std::int32_t>(grid.height) - 1, 0};
    auto geometry = std::make_shared<const sdk::Geometry>(2, lo, hi, std::move(mask), neighbours(),
                                                          directions(), space);

    // The map decides the box: a saved world repeats it, anything else is a mistake.
    const json box = {{"min", {lo.x, lo.y}}, {"max", {hi.x, hi.y}}};
    if (world.contains("bounds") && world["bounds"] != box)
      throw sdk::Error(sdk::codes::kBadWorld, "bounds: " + world["bounds"].dump() +
                                                  " differ from the map's " + box.dump() +
                                                  " (leave bounds out: the map decides them)");
    world["bounds"] = box;
    sdk::RoomMap regions = convert_metre_fields(world, frame, *geometry);
    for (const char* key : {"map", "frame"}) world.erase(key);

    wf::WorldDocument doc = wf::parse_world(world.dump(), 2);
    for (auto& [room, area] : regions)
      if (!doc.rooms.emplace(room, std::move(area)).second)
        throw sdk::Error(sdk::codes::kBadWorld,
                         "rooms: '" + room + "' is given both as a region and in rooms");
    wf::check_placement(doc, *geometry);
    return wf::make_state(std::move(doc), std::move(geometry));
  }

  std::string do_save(const sdk::WorldState& state) const override {
    const auto* space =
        state.geometry ? dynamic_cast<const MapSpace*>(state.geometry->continuous()) : nullptr;
    if (space == nullptr)
      throw sdk::Error(sdk::codes::kInternal, "ros_map: cannot save a world it did not load");
    const MapFrame& f = space->frame();
    const json frame = {{"resolution", f.resolution},
                        {"origin", {f.origin_x, f.origin_y}},
                        {"cell_centre", "origin + (cell + 0.5) * resolution"}};
    return wf::write_world(state,
                           {{"map", json(space->yaml_path()).dump()}, {"frame", frame.dump()}});
  }

  int do_dims() const override { return 2; }

 private:
  const double inflation_radius_;
  const bool inflate_unknown_;
  const int lethal_;
  const std::uint64_t max_cells_;
  const std::uint64_t max_file_bytes_;
};

}  // namespace
}  // namespace flipper::plugins::ros_map

FLIPPER_PLUGIN(flipper::plugins::ros_map::RosMapWorld, world, "ros_map", FLIPPER_PLUGIN_VERSION,
               "2-D world from a ROS map_server occupancy grid (YAML + PGM, Nav2 semantics), "
               "regions and positions in metres, inflation radius")
