#pragma once
/// @file plan_frame.hpp
/// Cells to metres for plans leaving Flipper (docs/ros2.md, frame `map`):
///   2-D grid:  p = origin + resolution * (x, y, 0)     world.resolution (m), world.origin (m)
///   3-D world: p = origin + r * (x + ½, y + ½, z + ½)  r = world.params.resolution: the octree's
///              own metric coordinates (cell centres), so the plan lands where the map's
///              obstacles are; world.resolution must stay 1 there.
/// Orientation: yaw about +z towards the next pose's xy (vertical moves and the last pose keep
/// the previous yaw; a plan with no horizontal move faces yaw 0).

#include <Eigen/Geometry>
#include <vector>

#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/geometry.hpp"

namespace flipper::kernel {
class Config;
}

namespace flipper::dds {

struct Pose {
  Eigen::Vector3d position;
  Eigen::Quaterniond orientation;
};

class PlanFrame {
 public:
  /// From the config (throws sdk::Error(bad_config) for a 3-D world with world.resolution != 1).
  static PlanFrame from_config(const kernel::Config& config, int dims);
  explicit PlanFrame(const Eigen::Affine3d& cell_to_map) : cell_to_map_(cell_to_map) {}

  Eigen::Vector3d to_metres(const sdk::Cell& c) const;
  /// The robot's start cell, then one pose per cell entered, in order.
  std::vector<Pose> poses(const sdk::Cell& start, const std::vector<sdk::TraceStep>& trace) const;
  const Eigen::Affine3d& transform() const { return cell_to_map_; }

 private:
  Eigen::Affine3d cell_to_map_;
};

}  // namespace flipper::dds
