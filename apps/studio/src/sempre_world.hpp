#pragma once
// The world of a /sempre `(:context ...)` (docs/sempre.md § "The context world"):
//   {"robot": [x, y, [[color, shape], ...]],
//    "world": [[x, y, "wall", null, null], [x, y, "item", color, shape], ...],
//    "rooms": {"room1": [[x, y], ...], ...}}
// as the protocol's world object (docs/protocol.md § "World object"), which the session's world
// plugin then loads and checks like any other world.
#include <string>
#include <string_view>

namespace flipper::studio {

/// The world object's JSON text. Throws sdk::Error(bad_world) naming the entry that is not of
/// the context's shape (the world plugin checks the rest: robot on a wall, size, ...).
std::string sempre_context_world(std::string_view context_json);

}  // namespace flipper::studio
