#pragma once
/// @file world.hpp
/// The world: immutable geometry (which cells are free, how the robot may step between them,
/// what direction words mean) shared by every copy, plus the small mutable state the language
/// changes (robot cell, items, held items). Rooms are named areas, also shared.
///
/// A world plugin reads and writes the world object of the session protocol for its kind of
/// space (2-D grid with walls, 3-D OctoMap...) and validates it. Everything the executor and the
/// planners need is in `Geometry` and `WorldState`, so a 3-D world is one more implementation,
/// not a special case in the kernel.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/export.hpp"
#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Optional continuous view of free space, for sampling planners (OMPL). Coordinates are in cell
/// units: the centre of cell (i, j, k) is (i, j, k). Thread-safe for concurrent const calls.
class FLIPPER_SDK_API ContinuousSpace {
 public:
  virtual ~ContinuousSpace();
  /// Whether the robot body fits at point p (z ignored in 2-D).
  virtual bool is_state_valid(const double p[3]) const = 0;
  /// Whether the straight motion a->b is collision-free (checked at `resolution` steps or exactly).
  virtual bool is_motion_valid(const double a[3], const double b[3]) const = 0;
};

/// Immutable geometry of a world: a bounding box, a free-cell mask over it, the neighbourhood
/// (in the order that breaks path ties), and direction words. Shared between world copies.
class FLIPPER_SDK_API Geometry {
 public:
  /// @param dims 2 or 3. @param min,max inclusive bounds (z = 0 for 2-D).
  /// @param free_mask one byte per cell of the box, x fastest, then y, then z; non-zero = free.
  /// @param neighbour_offsets step offsets in tie order (2-D: right, left, up, down).
  /// @param directions direction words and their unit offsets (`move` uses them).
  Geometry(int dims, Cell min, Cell max, std::vector<std::uint8_t> free_mask,
           std::vector<Cell> neighbour_offsets,
           std::vector<std::pair<std::string, Cell>> directions,
           std::shared_ptr<const ContinuousSpace> continuous = nullptr);
  ~Geometry();

  int dims() const { return dims_; }
  Cell min() const { return min_; }
  Cell max() const { return max_; }
  bool in_bounds(Cell c) const {
    return c.x >= min_.x && c.x <= max_.x && c.y >= min_.y && c.y <= max_.y && c.z >= min_.z &&
           c.z <= max_.z;
  }
  /// Inside the box and not blocked.
  bool is_free(Cell c) const { return in_bounds(c) && free_[index(c)] != 0; }
  /// Dense index of an in-bounds cell (x fastest). Precondition: in_bounds(c).
  std::size_t index(Cell c) const {
    return static_cast<std::size_t>(c.x - min_.x) +
           sx_ * (static_cast<std::size_t>(c.y - min_.y) +
                  sy_ * static_cast<std::size_t>(c.z - min_.z));
  }
  Cell cell_at(std::size_t index) const;
  std::size_t cell_count() const { return free_.size(); }
  std::size_t size_x() const { return sx_; }
  std::size_t size_y() const { return sy_; }
  std::size_t size_z() const { return sz_; }
  const std::vector<std::uint8_t>& free_mask() const { return free_; }
  const std::vector<Cell>& neighbour_offsets() const { return neighbours_; }
  /// Unit offset of a direction word, if this world knows it.
  std::optional<Cell> direction(std::string_view word) const;
  const std::vector<std::pair<std::string, Cell>>& directions() const { return directions_; }
  /// All free cells, sorted (computed once).
  const Area& free_cells() const { return free_cells_; }
  /// May be null: then sampling planners fall back to the cell mask.
  const ContinuousSpace* continuous() const { return continuous_.get(); }

 private:
  int dims_;
  Cell min_, max_;
  std::size_t sx_, sy_, sz_;
  std::vector<std::uint8_t> free_;
  std::vector<Cell> neighbours_;
  std::vector<std::pair<std::string, Cell>> directions_;
  std::shared_ptr<const ContinuousSpace> continuous_;
  Area free_cells_;
};

/// An item: ids are unique within a world and stable for a session.
struct ItemInfo {
  std::int64_t id = 0;
  std::string color;
  std::string shape;
  friend bool operator==(const ItemInfo&, const ItemInfo&) = default;
};

/// An item lying on a cell. Several may share a cell; order matters (§8 tie rules).
struct LyingItem {
  ItemInfo item;
  Cell at;
  friend bool operator==(const LyingItem&, const LyingItem&) = default;
};

using RoomMap = std::map<std::string, Area>;

/// A world state: a value type, cheap to copy (geometry and rooms are shared, immutable).
struct FLIPPER_SDK_API WorldState {
  std::shared_ptr<const Geometry> geometry;
  std::shared_ptr<const RoomMap> rooms;
  Cell robot;
  std::vector<LyingItem> items;   ///< lying items in world order (a dropped item goes last)
  std::vector<ItemInfo> held;     ///< held items in the order they were picked
  std::int64_t next_item_id = 0;  ///< next id to assign to a new item

  /// Same robot cell, lying items (with positions and order), held items, rooms and geometry.
  bool same_state(const WorldState& other) const;
};

/// What the host lets one world cost (docs/worlds.md § "Limits"). A world plugin refuses a world
/// beyond them before it allocates it: more cells than `max_cells` with Error(world_too_large)
/// ("the world has N cells; the limit is world.max_cells = M", world_format::check_cells words
/// it), a file the world names larger than `max_file_bytes` with Error(file_too_large). The
/// defaults are the largest limits a host may set, for callers without a configuration.
struct WorldLimits {
  std::uint64_t max_cells = std::uint64_t{1} << 28;       ///< the host's world.max_cells
  std::uint64_t max_file_bytes = std::uint64_t{1} << 40;  ///< the host's input.max_file_bytes
};

/// A world written for the other number of dimensions (a 3-D world given to a 2-D plugin): code
/// bad_world, the message is the reader's own complaint; the host adds a hint naming the world
/// plugins that read such worlds (docs/worlds.md § "Hints"). world_format::parse_world throws it.
class FLIPPER_SDK_API OtherDimsError : public Error {
 public:
  OtherDimsError(int world_dims, const std::string& message);
  ~OtherDimsError() override;
  /// The dimensions of the world that was given (2 or 3).
  int world_dims() const noexcept { return world_dims_; }

 private:
  int world_dims_;
};

/// World plugin: the owner of the protocol's world object for one kind of space. It reads and
/// validates it (within the host's limits) and writes it, whole or in the two parts that change
/// from state to state (items and robot), so the host never reads or writes the format itself.
/// JSON crosses the boundary as text so no JSON library type is part of the ABI.
/// world_format.hpp holds helpers for the common parts of the format that a plugin may use.
class FLIPPER_SDK_API World : public Plugin {
 public:
  using Interface = World;
  ~World() override;

  /// Parses a world object (JSON text). Relative file references (e.g. "octomap") are resolved
  /// against `base_dir`. Throws Error(bad_world) naming the offending entry (OtherDimsError for
  /// a world of the other dimensions), Error(world_too_large) or Error(file_too_large) for a
  /// world beyond `limits`, checked before the plugin allocates the world's cells.
  WorldState load(std::string_view world_json, const std::string& base_dir,
                  const WorldLimits& limits = {}) const {
    return do_load(world_json, base_dir, limits);
  }
  /// The normalised world object (JSON text, one line) for this state: walls (or octomap), items
  /// with ids, robot with held items, rooms, bounds.
  std::string save(const WorldState& state) const { return do_save(state); }
  /// The value of "items" in `save(state)`, appended to `out` byte for byte as `save` writes it.
  /// Hosts write the states of one geometry as its static text plus these two parts.
  void save_items(std::string& out, const WorldState& state) const { do_save_items(out, state); }
  /// The value of "robot" in `save(state)`, appended to `out` byte for byte as `save` writes it.
  void save_robot(std::string& out, const WorldState& state) const { do_save_robot(out, state); }
  /// 2 or 3 (also declared in the plugin's sidecar: `DIMS` of flipper_add_plugin).
  int dims() const { return do_dims(); }

 protected:
  virtual WorldState do_load(std::string_view world_json, const std::string& base_dir,
                             const WorldLimits& limits) const = 0;
  virtual std::string do_save(const WorldState& state) const = 0;
  /// Default: world_format::append_items_json (the common format).
  virtual void do_save_items(std::string& out, const WorldState& state) const;
  /// Default: world_format::append_robot_json (the common format).
  virtual void do_save_robot(std::string& out, const WorldState& state) const;
  virtual int do_dims() const = 0;
};

template <>
struct KindOf<World> {
  static constexpr PluginKind value = PluginKind::world;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
