// World texts by version: static text once, items and robot per state (world_texts.hpp).
#include "world_texts.hpp"

#include <charconv>
#include <nlohmann/json.hpp>

#include "flipper/toolkit/json/raw_members.hpp"

namespace flipper::kernel {
namespace {

constexpr std::size_t kVersionsKept = 4;

}  // namespace

std::string WorldTexts::save(const sdk::WorldState& state) const {
  std::string text = world_().call("save", [&](const sdk::World& w) { return w.save(state); });
  // The answer is one line: normalise a plugin that writes multi-line text.
  if (text.find('\n') != std::string::npos) text = nlohmann::json::parse(text).dump();
  return text;
}

namespace {

bool same_geometry(const sdk::Geometry& a, const sdk::Geometry& b) {
  // A continuous space (3-D obstacles) is plugin data the kernel cannot compare.
  return a.continuous() == nullptr && b.continuous() == nullptr && a.dims() == b.dims() &&
         a.min() == b.min() && a.max() == b.max() &&
         a.neighbour_offsets() == b.neighbour_offsets() && a.directions() == b.directions() &&
         a.free_mask() == b.free_mask();
}

bool same_rooms(const std::shared_ptr<const sdk::RoomMap>& a,
                const std::shared_ptr<const sdk::RoomMap>& b) {
  return a == b || (a && b && *a == *b);
}

}  // namespace

void WorldTexts::intern(sdk::WorldState& state) const {
  if (!state.geometry) return;
  for (const auto& v : versions_)
    if ((v->geometry == state.geometry || same_geometry(*v->geometry, *state.geometry)) &&
        same_rooms(v->rooms, state.rooms)) {
      state.geometry = v->geometry;
      state.rooms = v->rooms;
      return;
    }
}

WorldTexts::Version& WorldTexts::find_or_make(const sdk::WorldState& state) {
  for (std::size_t i = 0; i < versions_.size(); ++i)
    if (versions_[i]->geometry == state.geometry && versions_[i]->rooms == state.rooms) {
      if (i != 0) std::swap(versions_[i], versions_[0]);
      return *versions_[0];
    }
  auto v = std::make_unique<Version>();
  v->id = next_id_++;
  v->geometry = state.geometry;
  v->rooms = state.rooms;
  const std::string text = save(state);
  // The geometry text: every member but items and robot, in the plugin's order.
  const auto members = toolkit::json::top_level_members(text);
  std::string_view items, robot;
  v->geometry_text.push_back('{');  // (a new Version: the text is empty)
  for (const auto& m : members) {
    if (m.key == "\"items\"") {
      items = m.value;
    } else if (m.key == "\"robot\"") {
      robot = m.value;
    } else {
      if (v->geometry_text.size() > 1) v->geometry_text += ',';
      v->geometry_text.append(m.key).append(":").append(m.value);
    }
  }
  v->geometry_text += '}';
  // Split around the items and robot values when the kernel's writers reproduce them exactly.
  if (!items.empty() && !robot.empty() && items.data() < robot.data()) {
    const std::size_t items_at = static_cast<std::size_t>(items.data() - text.data());
    const std::size_t robot_at = static_cast<std::size_t>(robot.data() - text.data());
    v->before = text.substr(0, items_at);
    v->between = text.substr(items_at + items.size(), robot_at - items_at - items.size());
    v->after = text.substr(robot_at + robot.size());
    v->split = true;
    v->split = assemble(*v, state) == text;
  }
  if (versions_.size() == kVersionsKept) versions_.pop_back();
  versions_.insert(versions_.begin(), std::move(v));
  return *versions_.front();
}

std::string WorldTexts::assemble(const Version& v, const sdk::WorldState& state) const {
  std::string out;
  out.reserve(v.before.size() + v.between.size() + v.after.size() + 64 * state.items.size() + 64);
  const PluginRef<sdk::World>& world = world_();
  out += v.before;
  world.call("save_items", [&](const sdk::World& w) { w.save_items(out, state); });
  out += v.between;
  world.call("save_robot", [&](const sdk::World& w) { w.save_robot(out, state); });
  out += v.after;
  return out;
}

std::uint64_t WorldTexts::version(const sdk::WorldState& state) {
  return find_or_make(state).id;
}

std::string WorldTexts::full(const sdk::WorldState& state) {
  const Version& v = find_or_make(state);
  return v.split ? assemble(v, state) : save(state);
}

std::string WorldTexts::changes(const sdk::WorldState& state) {
  const Version& v = find_or_make(state);
  if (!v.split) return save(state);
  const PluginRef<sdk::World>& world = world_();
  std::string out = "{\"items\":";
  out.reserve(32 + 64 * state.items.size());
  world.call("save_items", [&](const sdk::World& w) { w.save_items(out, state); });
  out += ",\"robot\":";
  world.call("save_robot", [&](const sdk::World& w) { w.save_robot(out, state); });
  out += '}';
  return out;
}

const std::string& WorldTexts::geometry(const sdk::WorldState& state) {
  return find_or_make(state).geometry_text;
}

}  // namespace flipper::kernel
