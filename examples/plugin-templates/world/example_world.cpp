// example_world: an open 2-D field — every cell of the bounds is free, there are no walls — in the
// protocol's common world format (flipper/sdk/world_format.hpp reads, checks and writes it). The
// robot steps right, left, up and down (the tie order of shortest paths), and with `diagonal`
// also diagonally.
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/errors.hpp>
#include <flipper/sdk/plugin.hpp>
#include <flipper/sdk/world.hpp>
#include <flipper/sdk/world_format.hpp>

#include <memory>
#include <string>
#include <vector>

namespace example_world {

namespace sdk = flipper::sdk;
namespace wf = flipper::sdk::world_format;
namespace param = flipper::sdk::param;

// Each parameter written once: name, default, range, description.
constexpr param::Bool kDiagonal{"diagonal", false,
                                "also step diagonally (8 neighbours instead of 4)"};
constexpr param::Int<std::uint64_t> kMaxCells{"max_cells", 1000000, 1, std::nullopt,
                                              "largest field loaded, in cells of its bounds"};

class ExampleWorld : public sdk::World {
 public:
  explicit ExampleWorld(const sdk::Params& p)
      : diagonal_(param::get(p, kDiagonal)), max_cells_(param::get(p, kMaxCells)) {}
  static sdk::ParamSchema schema() { return param::schema(kDiagonal, kMaxCells); }

 protected:
  sdk::WorldState do_load(std::string_view text, const std::string&,
                          const sdk::WorldLimits& limits) const override {
    wf::WorldDocument doc = wf::parse_world(text, 2);
    if (doc.has_walls || doc.octomap)
      throw sdk::Error(sdk::codes::kBadWorld,
                       std::string(doc.has_walls ? "walls" : "octomap") +
                           ": example_world is an open field; obstacles need another world plugin");
    if (!doc.extra.empty())
      throw sdk::Error(sdk::codes::kBadWorld,
                       doc.extra.begin()->first + ": not a field of example_world's worlds");
    const wf::Bounds box = wf::effective_bounds(doc);
    const auto cells = static_cast<std::uint64_t>(box.max.x - box.min.x + 1) *
                       static_cast<std::uint64_t>(box.max.y - box.min.y + 1);
    if (cells > max_cells_)
      throw sdk::Error(sdk::codes::kBadWorld,
                       "bounds: " + std::to_string(cells) +
                           " cells; the limit is max_cells = " + std::to_string(max_cells_));
    wf::check_cells(cells, limits);  // and the host's limit (world.max_cells)
    std::vector<sdk::Cell> steps = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    if (diagonal_) steps.insert(steps.end(), {{1, 1, 0}, {-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}});
    auto geometry = std::make_shared<const sdk::Geometry>(
        2, box.min, box.max, std::vector<std::uint8_t>(static_cast<std::size_t>(cells), 1), steps,
        std::vector<std::pair<std::string, sdk::Cell>>{
            {"up", {0, 1, 0}}, {"down", {0, -1, 0}}, {"left", {-1, 0, 0}}, {"right", {1, 0, 0}}});
    wf::check_placement(doc, *geometry);
    return wf::make_state(std::move(doc), std::move(geometry));
  }

  std::string do_save(const sdk::WorldState& state) const override {
    return wf::write_world(state);
  }

  int do_dims() const override { return 2; }

 private:
  const bool diagonal_;
  const std::uint64_t max_cells_;
};

}  // namespace example_world

FLIPPER_PLUGIN(example_world::ExampleWorld, world, "example_world", FLIPPER_PLUGIN_VERSION,
               "An open 2-D field without walls (4 or 8 neighbours)")
