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

/// World plugin: reads, validates and writes the protocol's world object for one kind of space.
/// JSON crosses the boundary as text so no JSON library type is part of the ABI.
class FLIPPER_SDK_API World : public Plugin {
 public:
  using Interface = World;
  ~World() override;

  /// Parses a world object (JSON text). Relative file references (e.g. "octomap") are resolved
  /// against `base_dir`. Throws Error(bad_world) naming the offending entry.
  WorldState load(std::string_view world_json, const std::string& base_dir) const {
    return do_load(world_json, base_dir);
  }
  /// The normalised world object (JSON text) for this state: walls (or octomap), items with ids,
  /// robot with held items, rooms, bounds.
  std::string save(const WorldState& state) const { return do_save(state); }
  /// 2 or 3.
  int dims() const { return do_dims(); }

 protected:
  virtual WorldState do_load(std::string_view world_json, const std::string& base_dir) const = 0;
  virtual std::string do_save(const WorldState& state) const = 0;
  virtual int do_dims() const = 0;
};

template <>
struct KindOf<World> {
  static constexpr PluginKind value = PluginKind::world;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
