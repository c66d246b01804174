#pragma once
/// @file world_format.hpp
/// Shared helpers for world plugins: reading and writing the parts of the session protocol's
/// world object that every kind of space has in common (items with ids, the robot with what it
/// holds, rooms, bounds, blocked points), with `bad_world` errors that name the offending entry
/// (`items[3]: x must be an integer`, `rooms: duplicate room name "room2"`).
///
/// A world plugin parses the text with `parse_world`, decides the bounds (`default_bounds` when
/// absent), builds its `Geometry`, checks placement with `check_placement` and assembles the
/// state with `make_state`, checking the box with `check_cells` before it allocates the mask.
/// `write_world` renders a state back, with the plugin's own fields
/// (e.g. "walls" or "octomap") passed as JSON text. No JSON library type appears here.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace world_format {

/// Inclusive box; z = 0 for 2-D worlds.
struct Bounds {
  Cell min;
  Cell max;
  friend bool operator==(const Bounds&, const Bounds&) = default;
};

/// The common fields of a world object, checked for types and shapes (not yet for placement,
/// which needs the plugin's geometry). Items carry ids: explicit ones are kept, missing ones are
/// assigned in order (lying items, then held items) with the smallest id not used explicitly.
struct WorldDocument {
  int dims = 2;
  std::vector<Cell> walls;             ///< "walls" (sorted, duplicates removed); empty if absent
  bool has_walls = false;              ///< whether "walls" was present
  std::optional<std::string> octomap;  ///< "octomap" file name, if present (not resolved)
  std::vector<LyingItem> items;        ///< in world order
  Cell robot;
  std::vector<ItemInfo> holding;  ///< in picking order
  RoomMap rooms;
  std::vector<std::pair<std::string, std::vector<Cell>>> room_points;  ///< as written (for errors)
  std::optional<Bounds> bounds;                                        ///< explicit "bounds"
  std::int64_t next_item_id = 0;  ///< one more than the largest id
  /// Other top-level fields, as JSON text, for plugin-specific keys (e.g. a resolution).
  std::map<std::string, std::string> extra;
};

/// Parses a world object for a space of `dims` (2 or 3) dimensions. Points are arrays of `dims`
/// integers; item and robot positions are objects with "x", "y" (and "z" in 3-D). Rejects
/// malformed text, wrong types, duplicate keys (in particular duplicate room names), duplicate
/// item ids, a missing robot and empty bounds with Error(bad_world) naming the entry, and a world
/// that reads in the other dimensions with OtherDimsError (so the host can name the plugins that
/// read it). Unknown top-level fields are kept in `extra`; unknown fields inside items and the
/// robot are ignored.
FLIPPER_SDK_API WorldDocument parse_world(std::string_view json, int dims);

/// The smallest box holding every wall, item, room point and the robot (the protocol's default).
FLIPPER_SDK_API Bounds default_bounds(const WorldDocument& doc);

/// The explicit bounds, or the default ones.
FLIPPER_SDK_API Bounds effective_bounds(const WorldDocument& doc);

/// Cells of the box, counted in 64 bits (0 for an empty box).
FLIPPER_SDK_API std::uint64_t cell_count(const Bounds& box);

/// Refuses more than `limits.max_cells` cells with Error(world_too_large): "the world has N
/// cells; the limit is world.max_cells = M". Call it before allocating anything per cell.
FLIPPER_SDK_API void check_cells(std::uint64_t cells, const WorldLimits& limits);

/// Checks that walls and room points lie inside the bounds, and that the robot and every item
/// lie on free cells of `geometry`: `robot (2,6) is on a wall`, `items[4] (id 4) at (20,3) is
/// outside the bounds`, `walls[7] (20,3) is outside the bounds`. Throws Error(bad_world).
FLIPPER_SDK_API void check_placement(const WorldDocument& doc, const Geometry& geometry);

/// Assembles the state (moves items and rooms out of `doc`).
FLIPPER_SDK_API WorldState make_state(WorldDocument&& doc,
                                      std::shared_ptr<const Geometry> geometry);

/// A plugin-specific top-level field for `write_world`: key and value as JSON text.
struct RawField {
  std::string key;
  std::string json;
};

/// Renders the normalised world object: the `fields` first (in the given order, e.g. "walls"),
/// then "items" (with ids, in world order), "robot" (with "holding"), "rooms" (by name, points
/// sorted) and "bounds" (the geometry's box). Throws Error(internal) if a field is not JSON.
FLIPPER_SDK_API std::string write_world(const WorldState& state,
                                        const std::vector<RawField>& fields = {});

/// The "items" array and the "robot" object exactly as write_world writes them, appended to `out`
/// (also used by hosts that assemble a world from cached static text).
FLIPPER_SDK_API void append_items_json(std::string& out, const WorldState& state, int dims);
FLIPPER_SDK_API void append_robot_json(std::string& out, const WorldState& state, int dims);

/// JSON text of a point list: `[[x,y],...]` (or `[x,y,z]` points when dims == 3).
FLIPPER_SDK_API std::string points_json(const std::vector<Cell>& points, int dims);

/// "(x,y)" or "(x,y,z)", as used in messages.
FLIPPER_SDK_API std::string describe(const Cell& c, int dims);

}  // namespace world_format
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
