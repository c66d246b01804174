#pragma once
// A study task's goal (docs/studio.md §7 "Goals"): either a world the participant's world must
// equal (the robot's cell, held and lying items; ids and order ignored), or a predicate over the
// world that any of the many worlds meeting it satisfies: the robot in a room or at a cell, items
// of a colour or shape lying in a room or held, all of them or an exact count.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace flipper::studio {

class TaskGoal {
 public:
  /// One `items` condition: the items matching `color`/`shape` (empty: any) are held, or lie in
  /// `room`; `count`: exactly that many do (nullopt: all of them do, and there is at least one).
  struct Items {
    std::string color, shape, room;
    bool held = false;
    std::optional<std::int64_t> count;
  };

  TaskGoal() = default;  ///< no goal
  static TaskGoal of_world(nlohmann::json world);
  /// A predicate from the study file's `goal:` map; `start` is the task's start world (rooms
  /// named must be in it). Throws sdk::Error(bad_config) "study FILE: KEY: ..." naming the key.
  static TaskGoal of_predicate(const YAML::Node& spec, const nlohmann::json& start,
                               const std::string& study, const std::string& key);

  bool empty() const { return !world_.is_object() && !predicate_; }
  /// Whether `world` (a world object as the session writes it) meets the goal.
  bool reached(const nlohmann::json& world) const;
  /// The goal world (null for a predicate or none): what the page draws.
  const nlohmann::json& world() const { return world_; }
  /// The predicate as the study file gave it, normalised (null for a world or none).
  nlohmann::json predicate() const;

 private:
  nlohmann::json world_;
  bool predicate_ = false;
  std::string robot_in_;
  std::optional<std::vector<std::int64_t>> robot_at_;
  std::vector<Items> items_;
};

}  // namespace flipper::studio
