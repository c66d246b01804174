#include "task_goal.hpp"

#include <algorithm>
#include <set>
#include <utility>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
using Json = nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& study, const std::string& key, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadConfig, "study " + study + ": " + key + ": " + what);
}

std::string goal_member_text(const Json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// A world's robot cell, held items and lying items, ids and order ignored: what a world goal
// compares.
struct Digest {
  std::vector<std::int64_t> robot;
  std::vector<std::string> held, lying;
  bool operator==(const Digest&) const = default;
};

Digest digest(const Json& w) {
  Digest d;
  const Json robot = w.value("robot", Json::object());
  for (const char* k : {"x", "y", "z"}) d.robot.push_back(robot.value(k, std::int64_t{0}));
  for (const auto& h : robot.value("holding", Json::array()))
    d.held.push_back(goal_member_text(h, "color") + "/" + goal_member_text(h, "shape"));
  for (const auto& i : w.value("items", Json::array()))
    d.lying.push_back(std::to_string(i.value("x", 0)) + "," + std::to_string(i.value("y", 0)) +
                      "," + std::to_string(i.value("z", 0)) + "/" + goal_member_text(i, "color") +
                      "/" + goal_member_text(i, "shape"));
  std::sort(d.held.begin(), d.held.end());
  std::sort(d.lying.begin(), d.lying.end());
  return d;
}

// The cells of a room of `world` ([x, y] or [x, y, z] lists), empty when it has no such room.
std::set<std::vector<std::int64_t>> room_cells(const Json& world, const std::string& room) {
  std::set<std::vector<std::int64_t>> cells;
  const Json rooms = world.value("rooms", Json::object());
  if (!rooms.is_object() || !rooms.contains(room) || !rooms[room].is_array()) return cells;
  for (const auto& c : rooms[room]) {
    if (!c.is_array() || c.size() < 2) continue;
    std::vector<std::int64_t> cell;
    for (const auto& v : c) cell.push_back(v.is_number_integer() ? v.get<std::int64_t>() : 0);
    if (cell.size() == 2) cell.push_back(0);
    cells.insert(std::move(cell));
  }
  return cells;
}

std::vector<std::int64_t> cell_of(const Json& thing) {
  return {thing.value("x", std::int64_t{0}), thing.value("y", std::int64_t{0}),
          thing.value("z", std::int64_t{0})};
}

bool matches(const TaskGoal::Items& want, const Json& item) {
  return (want.color.empty() || goal_member_text(item, "color") == want.color) &&
         (want.shape.empty() || goal_member_text(item, "shape") == want.shape);
}

std::string scalar(const YAML::Node& n, const std::string& study, const std::string& key) {
  if (!n.IsScalar()) fail(study, key, "must be text");
  return n.as<std::string>();
}

void check_keys(const YAML::Node& map, const std::set<std::string>& known, const std::string& study,
                const std::string& key) {
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    if (known.count(k) == 0) {
      std::string list;
      for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
      fail(study, key, "unknown key '" + k + "' (known: " + list + ")");
    }
  }
}

std::string room_of(const YAML::Node& n, const Json& start, const std::string& study,
                    const std::string& key) {
  std::string room = scalar(n, study, key);
  if (room_cells(start, room).empty())
    fail(study, key, "the task's start world has no room '" + room + "'");
  return room;
}

}  // namespace

TaskGoal TaskGoal::of_world(Json world) {
  TaskGoal g;
  g.world_ = std::move(world);
  return g;
}

TaskGoal TaskGoal::of_predicate(const YAML::Node& spec, const Json& start, const std::string& study,
                                const std::string& key) {
  if (!spec.IsMap() || spec.size() == 0)
    fail(study, key, "a goal is a world file or a map of robot_in, robot_at and items");
  check_keys(spec, {"robot_in", "robot_at", "items"}, study, key);
  TaskGoal g;
  g.predicate_ = true;
  if (spec["robot_in"]) g.robot_in_ = room_of(spec["robot_in"], start, study, key + ".robot_in");
  if (const YAML::Node at = spec["robot_at"]) {
    if (!at.IsSequence() || at.size() < 2 || at.size() > 3)
      fail(study, key + ".robot_at", "must be a cell [x, y] or [x, y, z]");
    std::vector<std::int64_t> cell;
    for (const auto& v : at) {
      try {
        cell.push_back(v.as<std::int64_t>());
      } catch (const YAML::Exception&) {
        fail(study, key + ".robot_at", "'" + v.as<std::string>() + "' is not an integer");
      }
    }
    if (cell.size() == 2) cell.push_back(0);
    g.robot_at_ = std::move(cell);
  }
  if (const YAML::Node items = spec["items"]) {
    if (!items.IsSequence() || items.size() == 0)
      fail(study, key + ".items", "must be a non-empty list of {color, shape, in | held, count}");
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string at = key + ".items[" + std::to_string(i) + "]";
      const YAML::Node n = items[i];
      if (!n.IsMap()) fail(study, at, "must be a map of color, shape, in | held, count");
      check_keys(n, {"color", "shape", "in", "held", "count"}, study, at);
      Items it;
      if (n["color"]) it.color = scalar(n["color"], study, at + ".color");
      if (n["shape"]) it.shape = scalar(n["shape"], study, at + ".shape");
      if (n["in"]) it.room = room_of(n["in"], start, study, at + ".in");
      if (n["held"]) it.held = scalar(n["held"], study, at + ".held") == "true";
      if (it.held == !it.room.empty())
        fail(study, at, "give exactly one of 'in: ROOM' and 'held: true'");
      if (const YAML::Node c = n["count"]; c && scalar(c, study, at + ".count") != "all") {
        try {
          it.count = c.as<std::int64_t>();
        } catch (const YAML::Exception&) {
          fail(study, at + ".count",
               "must be 'all' or a number of items, not '" + c.as<std::string>() + "'");
        }
        if (*it.count < 0) fail(study, at + ".count", "must not be negative");
      }
      g.items_.push_back(std::move(it));
    }
  }
  return g;
}

bool TaskGoal::reached(const Json& world) const {
  if (world_.is_object()) return digest(world) == digest(world_);
  if (!predicate_) return false;
  const Json robot = world.value("robot", Json::object());
  if (!robot_in_.empty() && room_cells(world, robot_in_).count(cell_of(robot)) == 0) return false;
  if (robot_at_ && cell_of(robot) != *robot_at_) return false;
  const Json held = robot.value("holding", Json::array());
  const Json lying = world.value("items", Json::array());
  for (const auto& want : items_) {
    std::int64_t there = 0, matching = 0;
    for (const auto& h : held)
      if (matches(want, h)) {
        ++matching;
        there += want.held ? 1 : 0;
      }
    const auto cells =
        want.held ? std::set<std::vector<std::int64_t>>() : room_cells(world, want.room);
    for (const auto& i : lying)
      if (matches(want, i)) {
        ++matching;
        there += cells.count(cell_of(i)) != 0 ? 1 : 0;
      }
    if (want.count ? there != *want.count : (matching == 0 || there != matching)) return false;
  }
  return true;
}

Json TaskGoal::predicate() const {
  if (!predicate_) return nullptr;
  Json out = Json::object();
  if (!robot_in_.empty()) out["robot_in"] = robot_in_;
  if (robot_at_) out["robot_at"] = *robot_at_;
  if (!items_.empty()) {
    Json items = Json::array();
    for (const auto& i : items_) {
      Json j = Json::object();
      if (!i.color.empty()) j["color"] = i.color;
      if (!i.shape.empty()) j["shape"] = i.shape;
      if (i.held) j["held"] = true;
      if (!i.room.empty()) j["in"] = i.room;
      j["count"] = i.count ? Json(*i.count) : Json("all");
      items.push_back(std::move(j));
    }
    out["items"] = std::move(items);
  }
  return out;
}

}  // namespace flipper::studio
