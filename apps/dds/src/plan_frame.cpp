#include "flipper/dds/plan_frame.hpp"

#include <cmath>
#include <string_view>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {
// The octomap3d world plugin's `resolution` param: not a config key (the plugin's own schema
// declares and validates it), read from its section as written.
constexpr std::string_view kWorldResolutionParam = "world.params.resolution";
}  // namespace

PlanFrame PlanFrame::from_config(const kernel::Config& config, int dims) {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  const std::vector<double> given = config.get(kernel::keys::kWorldOrigin);
  if (given.size() < 2 || given.size() > 3)
    throw sdk::Error(
        sdk::codes::kBadConfig,
        "world.origin must list 2 or 3 numbers (metres), got " + std::to_string(given.size()));
  for (std::size_t i = 0; i < given.size(); ++i) origin[static_cast<int>(i)] = given[i];
  const double resolution = config.get(kernel::keys::kWorldResolution);
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (dims == 3) {
    if (resolution != 1.0)
      throw sdk::Error(sdk::codes::kBadConfig,
                       "world.resolution applies to 2-D grids; a 3-D world's plans use its own "
                       "metric coordinates (world.params.resolution)");
    // A param of the world plugin (octomap3d), not a config key: its own schema declares it.
    const std::string param(kWorldResolutionParam);
    const double r = config.has(param) ? config.get_double(param) : 1.0;
    t.translate(origin);
    t.scale(r);
    t.translate(Eigen::Vector3d(0.5, 0.5, 0.5));
  } else {
    t.translate(origin);
    t.scale(Eigen::Vector3d(resolution, resolution, 1.0));
  }
  return PlanFrame(t);
}

Eigen::Vector3d PlanFrame::to_metres(const sdk::Cell& c) const {
  return cell_to_map_ * Eigen::Vector3d(c.x, c.y, c.z);
}

std::vector<Pose> PlanFrame::poses(const sdk::Cell& start,
                                   const std::vector<sdk::TraceStep>& trace) const {
  std::vector<Pose> out;
  out.push_back({to_metres(start), Eigen::Quaterniond::Identity()});
  for (const auto& step : trace)
    if (step.act == sdk::TraceStep::Act::move)
      out.push_back({to_metres(step.cell), Eigen::Quaterniond::Identity()});
  // Yaw towards the next horizontal displacement; carried over vertical moves and to the end.
  double yaw = 0;
  std::vector<double> yaws(out.size(), 0.0);
  // The first pose faces where the robot goes first.
  for (std::size_t i = 0; i + 1 < out.size(); ++i) {
    const Eigen::Vector3d d = out[i + 1].position - out[i].position;
    if (std::abs(d.x()) > 1e-12 || std::abs(d.y()) > 1e-12) {
      yaw = std::atan2(d.y(), d.x());
      break;
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i + 1 < out.size()) {
      const Eigen::Vector3d d = out[i + 1].position - out[i].position;
      if (std::abs(d.x()) > 1e-12 || std::abs(d.y()) > 1e-12) yaw = std::atan2(d.y(), d.x());
    }
    yaws[i] = yaw;
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i].orientation = Eigen::AngleAxisd(yaws[i], Eigen::Vector3d::UnitZ());
  return out;
}

}  // namespace flipper::dds
