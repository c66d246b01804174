#pragma once
// Occupied space of a 3-D world: an OctoMap octree (read from a .bt file and/or filled from cell
// boxes), the robot body, and the FCL checks built on them: the cell free mask and the
// continuous view (ContinuousSpace) that sampling planners use.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_object.h>
#include <octomap/OcTree.h>

#include "flipper/sdk/world.hpp"
#include "obstacles.hpp"

namespace flipper::plugins::octomap3d {

struct Body {
  enum class Shape { box, sphere } shape = Shape::box;
  double size = 0.5;  ///< box edge / sphere diameter, in metres (cells are `resolution` metres)
};

/// The largest .bt file read, and the name of the limit for the refusal.
struct FileLimit {
  std::uint64_t bytes = 0;
  const char* name = "max_file_bytes";
};

/// Builds the octree at `resolution`: the .bt file (resolved against base_dir; its own
/// resolution is kept) plus every box and wall cell marked occupied.
/// Throws sdk::Error(bad_world) if the file cannot be read, not_a_regular_file for a FIFO,
/// device or directory (which would hang or never end), file_too_large above `limit`.
std::shared_ptr<octomap::OcTree> build_octree(const Obstacles& obstacles,
                                              const std::string& base_dir, double resolution,
                                              const FileLimit& limit);

/// Cells covered by the octree's occupied voxels (empty box if none): used for default bounds.
bool occupied_cell_box(const octomap::OcTree& tree, double resolution, CellBox& out);

/// FCL view of the world: the body against the octree. Coordinates in cell units (cell (i,j,k)
/// has its centre at (i,j,k)); the metric centre is ((i + 0.5) * resolution, ...), which is the
/// centre of the octree voxel of that cell. Immutable, so concurrent const calls are safe.
class FclSpace final : public sdk::ContinuousSpace {
 public:
  FclSpace(std::shared_ptr<const octomap::OcTree> tree, Body body, double resolution,
           CellBox bounds, Obstacles obstacles);

  bool is_state_valid(const double p[3]) const override;
  /// Sub-steps the segment at most a quarter cell apart (both ends included).
  bool is_motion_valid(const double a[3], const double b[3]) const override;

  /// Whether the body centred at cell-unit point p touches occupied space (bounds ignored).
  bool collides(const double p[3]) const;
  /// One byte per cell of `bounds` (x fastest, then y, then z): 1 = the body fits at its centre.
  std::vector<std::uint8_t> free_mask() const;

  const CellBox& bounds() const { return bounds_; }
  /// Obstacle description (boxes, walls, octomap name) as loaded, for `save`.
  const Obstacles& obstacles() const { return obstacles_; }
  const Body& body() const { return body_; }

 private:
  std::shared_ptr<const octomap::OcTree> tree_;
  std::unique_ptr<fcl::CollisionObjectd> tree_object_;  // null when nothing is occupied
  std::shared_ptr<fcl::CollisionGeometryd> body_shape_;
  Body body_;
  double resolution_;
  CellBox bounds_;
  Obstacles obstacles_;
};

}  // namespace flipper::plugins::octomap3d
