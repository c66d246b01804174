#pragma once
// What a 3-D world object says about occupied space: inclusive cell boxes ("boxes"), single
// cells ("walls") and an OctoMap file ("octomap"). The common fields (items, robot, rooms,
// bounds...) are read by the SDK's world_format helpers.
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/world_format.hpp"

namespace flipper::plugins::octomap3d {

namespace wf = flipper::sdk::world_format;

/// An inclusive box of cells.
struct CellBox {
  sdk::Cell min;
  sdk::Cell max;
};

struct Obstacles {
  std::vector<CellBox> boxes;
  std::vector<sdk::Cell> walls;
  std::optional<std::string> octomap;  ///< as written in the object (not resolved)
};

/// Takes the obstacle fields out of a parsed document: "boxes" from its extra fields (any other
/// extra field is an error: typos must not pass silently). Throws sdk::Error(bad_world).
Obstacles take_obstacles(wf::WorldDocument& doc);

/// The fields `write_world` puts first: "octomap", "boxes", "walls" (those that are present).
std::vector<wf::RawField> obstacle_fields(const Obstacles& obstacles);

}  // namespace flipper::plugins::octomap3d
