#pragma once
/// @file plan_publisher.hpp
/// `publish.plans: dds`: every accepted plan goes out as a ROS 2 nav_msgs/msg/Path on the
/// robot's plan topic, rt/<dds.namespace>/flipper/plan (names.hpp; ROS 2:
/// /<namespace>/flipper/plan, /flipper/plan in the root namespace), and its picks and drops as
/// flipper/msg/ActionList on .../flipper/actions. Both: reliable, TRANSIENT_LOCAL, keep-last 1
/// (a late subscriber gets the robot's latest plan, like a latched topic; ROS 2's default
/// volatile subscribers match too). The namespace says whose plan it is; plan_seq numbers the
/// plans on the robot's topic (1, 2, ... from this publisher's start, whichever session
/// accepted them).

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "flipper/dds/participant.hpp"
#include "flipper/dds/plan_frame.hpp"
#include "flipper/kernel/session.hpp"

namespace flipper::dds {

inline constexpr const char* kPlanTopic = "rt/flipper/plan";
inline constexpr const char* kActionsTopic = "rt/flipper/actions";
inline constexpr const char* kMapFrame = "map";

/// A session extension: installed on a session, it publishes the session's PlanAccepted events.
class PlanPublisher : public kernel::SessionExtension {
 public:
  PlanPublisher(std::shared_ptr<Participant> participant, PlanFrame frame,
                const std::string& ns = {});
  ~PlanPublisher() override;
  void attach(kernel::Session& session) override;
  void publish(const kernel::PlanAccepted& plan);
  /// Plans published so far.
  std::uint64_t published() const { return published_; }
  const std::string& plan_topic() const { return plan_topic_; }

 private:
  std::shared_ptr<Participant> participant_;
  PlanFrame frame_;
  std::string plan_topic_, actions_topic_;
  std::mutex mutex_;  // sessions of one node accept from their own threads
  dds_entity_t plan_writer_ = 0;
  dds_entity_t actions_writer_ = 0;
  std::uint64_t published_ = 0;
};

}  // namespace flipper::dds
