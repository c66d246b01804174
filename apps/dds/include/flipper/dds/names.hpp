#pragma once
/// @file names.hpp
/// Topic names under a node namespace, as ROS 2 names topics per robot (docs/ros2.md, "Topics and
/// types"): the node of namespace `robot1` uses rt/robot1/flipper/plan,
/// .../actions, .../request, .../answer (ROS 2: /robot1/flipper/plan, ...); the root namespace
/// (empty) uses rt/flipper/plan, ... The lexicon topic is one for all sites: rt/flipper/lexicon.

#include <string>

#include "flipper/dds/config_keys.hpp"

namespace flipper::dds {

/// "rt/<ns>/flipper/<leaf>", or "rt/flipper/<leaf>" when `ns` is empty.
std::string node_topic(const std::string& ns, const std::string& leaf);

/// Where the ROS 2 action `action` of namespace `ns` lives on DDS, as rcl_action and rmw name it:
/// "<ns>/<action>/_action/" ("<action>/_action/" in the root namespace). Its topics are
/// rq/<prefix><service>Request and rr/<prefix><service>Reply for the services send_goal,
/// get_result and cancel_goal, and rt/<prefix>feedback, rt/<prefix>status (docs/ros2.md, "Nav2").
std::string action_prefix(const std::string& ns, const std::string& action);

/// Throws sdk::Error(bad_config) unless `ns` is empty or one ROS 2 name token: a letter or `_`,
/// then letters, digits or `_`, at most 64 characters in all.
void check_namespace(const std::string& ns,
                     const std::string& key = std::string(keys::kNamespace.name));

}  // namespace flipper::dds
