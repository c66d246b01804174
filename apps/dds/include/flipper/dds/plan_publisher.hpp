#pragma once
/// @file plan_publisher.hpp
/// `publish.plans: dds`: every accepted plan goes out as a ROS 2 nav_msgs/msg/Path on
/// rt/flipper/plan (ROS 2: /flipper/plan) and its picks and drops as flipper/msg/ActionList on
/// rt/flipper/actions. Both: reliable, TRANSIENT_LOCAL, keep-last 1 (a late subscriber gets the
/// latest plan, like a latched topic; ROS 2's default volatile subscribers match too).

#include <cstdint>
#include <memory>
#include <string>

#include "flipper/dds/participant.hpp"
#include "flipper/dds/plan_frame.hpp"
#include "flipper/kernel/accepted_plan.hpp"

namespace flipper::dds {

inline constexpr const char* kPlanTopic = "rt/flipper/plan";
inline constexpr const char* kActionsTopic = "rt/flipper/actions";
inline constexpr const char* kMapFrame = "map";

class PlanPublisher : public kernel::AcceptedPlanObserver {
 public:
  PlanPublisher(std::shared_ptr<Participant> participant, PlanFrame frame);
  ~PlanPublisher() override;
  void on_accepted_plan(const kernel::AcceptedPlan& plan) override;
  /// Plans published so far.
  std::uint64_t published() const { return published_; }

 private:
  std::shared_ptr<Participant> participant_;
  PlanFrame frame_;
  dds_entity_t plan_writer_ = 0;
  dds_entity_t actions_writer_ = 0;
  std::uint64_t published_ = 0;
};

}  // namespace flipper::dds
