#include "occupancy.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::octomap3d {
namespace {

// Marks every voxel of `tree` whose centre lies in the metric box [lo, hi) as occupied (at the
// clamping maximum, so it is occupied whatever the tree's thresholds are). Works for a tree read
// from a .bt file at a resolution other than the plugin's.
void fill_metric_box(octomap::OcTree& tree, const double lo[3], const double hi[3]) {
  const double r = tree.getResolution();
  const double eps = 1e-6 * r;
  octomap::OcTreeKey klo, khi;
  if (!tree.coordToKeyChecked(lo[0] + eps, lo[1] + eps, lo[2] + eps, klo) ||
      !tree.coordToKeyChecked(hi[0] - eps, hi[1] - eps, hi[2] - eps, khi))
    throw sdk::Error(sdk::codes::kBadWorld,
                     "boxes: an obstacle lies outside the octree's coordinate range");
  const float occupied = tree.getClampingThresMaxLog();
  octomap::OcTreeKey k;
  for (unsigned x = klo[0]; x <= khi[0]; ++x)
    for (unsigned y = klo[1]; y <= khi[1]; ++y)
      for (unsigned z = klo[2]; z <= khi[2]; ++z) {
        k[0] = static_cast<octomap::key_type>(x);
        k[1] = static_cast<octomap::key_type>(y);
        k[2] = static_cast<octomap::key_type>(z);
        tree.setNodeValue(k, occupied, /*lazy_eval=*/true);
      }
}

void fill_cells(octomap::OcTree& tree, const CellBox& b, double res) {
  const double lo[3] = {b.min.x * res, b.min.y * res, b.min.z * res};
  const double hi[3] = {(b.max.x + 1) * res, (b.max.y + 1) * res, (b.max.z + 1) * res};
  fill_metric_box(tree, lo, hi);
}

}  // namespace

std::shared_ptr<octomap::OcTree> build_octree(const Obstacles& spec, const std::string& base_dir,
                                              double resolution, const FileLimit& limit) {
  auto tree = std::make_shared<octomap::OcTree>(resolution);
  if (spec.octomap) {
    std::filesystem::path path(*spec.octomap);
    if (path.is_relative()) path = std::filesystem::path(base_dir) / path;
    // stat, not open: opening a FIFO without a writer blocks.
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
      throw sdk::Error(sdk::codes::kBadWorld, "octomap: cannot read file " + path.string());
    if (!std::filesystem::is_regular_file(status))
      throw sdk::Error(sdk::codes::kNotARegularFile,
                       "octomap: " + path.string() + " is not a regular file");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec || size > limit.bytes)
      throw sdk::Error(sdk::codes::kFileTooLarge, "octomap: " + path.string() + " has " +
                                                      std::to_string(size) +
                                                      " bytes; the limit is " + limit.name + " = " +
                                                      std::to_string(limit.bytes));
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw sdk::Error(sdk::codes::kBadWorld, "octomap: cannot read file " + path.string());
    probe.close();
    if (!tree->readBinary(path.string()))
      throw sdk::Error(sdk::codes::kBadWorld,
                       "octomap: " + path.string() + " is not a readable .bt octree");
  }
  for (const auto& b : spec.boxes) fill_cells(*tree, b, resolution);
  for (const auto& w : spec.walls) fill_cells(*tree, CellBox{w, w}, resolution);
  tree->updateInnerOccupancy();
  return tree;
}

bool occupied_cell_box(const octomap::OcTree& tree, double resolution, CellBox& out) {
  bool any = false;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const double half = it.getSize() / 2;
    const auto c = it.getCoordinate();
    // Cells whose centres the leaf covers.
    auto lo = [&](double v) {
      return static_cast<std::int32_t>(std::ceil((v - half) / resolution - 0.5));
    };
    auto hi = [&](double v) {
      return static_cast<std::int32_t>(std::floor((v + half) / resolution - 0.5 - 1e-9));
    };
    const sdk::Cell mn{lo(c.x()), lo(c.y()), lo(c.z())};
    const sdk::Cell mx{hi(c.x()), hi(c.y()), hi(c.z())};
    if (mn.x > mx.x || mn.y > mx.y || mn.z > mx.z) continue;
    if (!any) {
      out = {mn, mx};
      any = true;
      continue;
    }
    out.min = {std::min(out.min.x, mn.x), std::min(out.min.y, mn.y), std::min(out.min.z, mn.z)};
    out.max = {std::max(out.max.x, mx.x), std::max(out.max.y, mx.y), std::max(out.max.z, mx.z)};
  }
  return any;
}

FclSpace::FclSpace(std::shared_ptr<const octomap::OcTree> tree, Body body, double resolution,
                   CellBox bounds, Obstacles obstacles)
    : tree_(std::move(tree)),
      body_(body),
      resolution_(resolution),
      bounds_(bounds),
      obstacles_(std::move(obstacles)) {
  if (tree_->size() > 0)
    tree_object_ = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::OcTreed>(tree_));
  if (body_.shape == Body::Shape::box)
    body_shape_ = std::make_shared<fcl::Boxd>(body_.size, body_.size, body_.size);
  else
    body_shape_ = std::make_shared<fcl::Sphered>(body_.size / 2);
}

bool FclSpace::collides(const double p[3]) const {
  if (!tree_object_) return false;
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = fcl::Vector3d((p[0] + 0.5) * resolution_, (p[1] + 0.5) * resolution_,
                                   (p[2] + 0.5) * resolution_);
  fcl::CollisionObjectd body(body_shape_, tf);
  fcl::CollisionRequestd request;  // one contact is enough: we only need yes/no
  fcl::CollisionResultd result;
  fcl::collide(tree_object_.get(), &body, request, result);
  return result.isCollision();
}

bool FclSpace::is_state_valid(const double p[3]) const {
  // The box of cells, extended by half a cell: every point rounds to an in-bounds cell.
  const double lo[3] = {bounds_.min.x - 0.5, bounds_.min.y - 0.5, bounds_.min.z - 0.5};
  const double hi[3] = {bounds_.max.x + 0.5, bounds_.max.y + 0.5, bounds_.max.z + 0.5};
  for (int i = 0; i < 3; ++i)
    if (!(p[i] >= lo[i] && p[i] < hi[i])) return false;
  return !collides(p);
}

bool FclSpace::is_motion_valid(const double a[3], const double b[3]) const {
  const double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.25)));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const double p[3] = {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]};
    if (!is_state_valid(p)) return false;
  }
  return true;
}

std::vector<std::uint8_t> FclSpace::free_mask() const {
  // Extents in 64 bits: max - min + 1 overflows int for boxes wider than 2^31 cells.
  const auto sx = static_cast<std::size_t>(std::int64_t{bounds_.max.x} - bounds_.min.x + 1);
  const auto sy = static_cast<std::size_t>(std::int64_t{bounds_.max.y} - bounds_.min.y + 1);
  const auto sz = static_cast<std::size_t>(std::int64_t{bounds_.max.z} - bounds_.min.z + 1);
  std::vector<std::uint8_t> mask(sx * sy * sz, 0);
  std::size_t i = 0;
  for (auto z = bounds_.min.z; z <= bounds_.max.z; ++z)
    for (auto y = bounds_.min.y; y <= bounds_.max.y; ++y)
      for (auto x = bounds_.min.x; x <= bounds_.max.x; ++x, ++i) {
        const double p[3] = {double(x), double(y), double(z)};
        mask[i] = collides(p) ? 0 : 1;
      }
  return mask;
}

}  // namespace flipper::plugins::octomap3d
