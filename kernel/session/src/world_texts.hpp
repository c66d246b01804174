#pragma once
/// @file world_texts.hpp
/// The texts of worlds in answers (docs/protocol.md § "Protocol versions"). A world's static part
/// (walls or other obstacles, rooms, bounds) depends only on its geometry and rooms, which every
/// state derived from one loaded world shares; only the robot, the lying items and the held items
/// change. So the plugin's text is taken apart once per *world version* (one geometry + rooms) into
/// static text around the "items" and "robot" values, and every later state of that version is
/// written by filling those two values in: the full form costs a copy of the static text, the
/// change-only form (`{"items":...,"robot":...}`) does not depend on the wall count at all.
///
/// The two values come from the plugin too (sdk::World::save_items, save_robot: the plugin owns
/// its format, docs/worlds.md). The split is checked when a version is made: the reassembled
/// text of the state it was made from must equal the plugin's whole text byte for byte; a plugin
/// whose parts do not reassemble keeps being asked for its whole text, in both forms.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/world.hpp"
#include "flipper/toolkit/json/raw_members.hpp"

namespace flipper::kernel {

class WorldTexts {
 public:
  using WorldPlugin = std::function<const PluginRef<sdk::World>&()>;
  /// `world` gives the session's current world plugin (a rebind may change it).
  explicit WorldTexts(WorldPlugin world) : world_(std::move(world)) {}

  /// Rebinds `state` to the geometry and rooms of a recent version with equal content, so a
  /// reloaded world (a client sending the same map again) keeps its version and its texts.
  void intern(sdk::WorldState& state) const;
  /// The version id of the state's geometry + rooms (made on first use; ids start at 1).
  std::uint64_t version(const sdk::WorldState& state);
  /// The full world object, byte-identical to the plugin's text.
  std::string full(const sdk::WorldState& state);
  /// `{"items":[...],"robot":{...}}` of the state, or the full text when the plugin's text does
  /// not split (see above).
  std::string changes(const sdk::WorldState& state);
  /// The version's world object without "items" and "robot" (walls, rooms, bounds, ...).
  const std::string& geometry(const sdk::WorldState& state);

 private:
  struct Version {
    std::uint64_t id = 0;
    std::shared_ptr<const sdk::Geometry> geometry;
    std::shared_ptr<const sdk::RoomMap> rooms;
    bool split = false;         ///< the static text below reassembles the plugin's text
    std::string before;         ///< text up to the items value
    std::string between;        ///< text between the items and the robot values
    std::string after;          ///< text after the robot value
    std::string geometry_text;  ///< the object without items and robot
  };
  Version& find_or_make(const sdk::WorldState& state);
  std::string assemble(const Version& v, const sdk::WorldState& state) const;
  /// The plugin's whole text, on one line (a multi-line text is normalised).
  std::string save(const sdk::WorldState& state) const;

  WorldPlugin world_;
  std::vector<std::unique_ptr<Version>> versions_;  // most recent first, a few kept
  std::uint64_t next_id_ = 1;
};

}  // namespace flipper::kernel
