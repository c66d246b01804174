#include "flipper/dds/plan_publisher.hpp"

#include <chrono>
#include <vector>

#include "flipper/dds/names.hpp"
#include "flipper/msg/Actions.h"
#include "nav_msgs/msg/Path.h"
#include "ros_time.hpp"

namespace flipper::dds {
namespace {

dds_entity_t latched_writer(Participant& p, const dds_topic_descriptor_t* desc, const char* name) {
  Qos qos;
  latched_qos(qos);
  return check(dds_create_writer(p.handle(), p.topic(desc, name), qos.q, nullptr),
               std::string("creating a writer on ") + name);
}

}  // namespace

PlanPublisher::PlanPublisher(std::shared_ptr<Participant> participant, PlanFrame frame,
                             const std::string& ns)
    : participant_(std::move(participant)),
      frame_(std::move(frame)),
      plan_topic_(node_topic(ns, "plan")),
      actions_topic_(node_topic(ns, "actions")) {
  plan_writer_ = latched_writer(*participant_, &nav_msgs_msg_dds__Path__desc, plan_topic_.c_str());
  actions_writer_ =
      latched_writer(*participant_, &flipper_msg_dds__ActionList__desc, actions_topic_.c_str());
}

PlanPublisher::~PlanPublisher() {
  if (plan_writer_ > 0) dds_delete(plan_writer_);
  if (actions_writer_ > 0) dds_delete(actions_writer_);
}

void PlanPublisher::attach(kernel::Session& session) {
  session.on<kernel::PlanAccepted>([this](const kernel::PlanAccepted& plan) { publish(plan); });
}

void PlanPublisher::publish(const kernel::PlanAccepted& plan) {
  std::lock_guard lock(mutex_);
  const auto stamp = now_stamp();
  char frame_id[] = "map";
  const std::vector<Pose> poses = frame_.poses(plan.before.robot, plan.outcome.trace);

  std::vector<geometry_msgs_msg_dds__PoseStamped_> stamped(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    auto& s = stamped[i];
    s.header_.stamp_ = stamp;
    s.header_.frame_id_ = frame_id;
    s.pose_.position_ = {poses[i].position.x(), poses[i].position.y(), poses[i].position.z()};
    const auto& q = poses[i].orientation;
    s.pose_.orientation_ = {q.x(), q.y(), q.z(), q.w()};
  }
  nav_msgs_msg_dds__Path_ path{};
  path.header_.stamp_ = stamp;
  path.header_.frame_id_ = frame_id;
  path.poses_._length = path.poses_._maximum = static_cast<uint32_t>(stamped.size());
  path.poses_._buffer = stamped.data();
  path.poses_._release = false;
  check(dds_write(plan_writer_, &path), "publishing a plan on " + plan_topic_);

  std::vector<flipper_msg_dds__Action_> acts;
  std::vector<std::string> colours, shapes;  // owners of the strings the samples point to
  colours.reserve(plan.outcome.trace.size());
  shapes.reserve(plan.outcome.trace.size());
  uint32_t pose_index = 0;
  static char pick[] = "pick", drop[] = "drop";
  for (const auto& step : plan.outcome.trace) {
    if (step.act == sdk::TraceStep::Act::move) {
      ++pose_index;
      continue;
    }
    const Eigen::Vector3d at = frame_.to_metres(step.cell);
    colours.push_back(step.item.color);
    shapes.push_back(step.item.shape);
    flipper_msg_dds__Action_ a{};
    a.kind_ = step.act == sdk::TraceStep::Act::pick ? pick : drop;
    a.pose_index_ = pose_index;
    a.position_ = {at.x(), at.y(), at.z()};
    a.item_id_ = step.item.id;
    a.color_ = colours.back().data();
    a.shape_ = shapes.back().data();
    acts.push_back(a);
  }
  flipper_msg_dds__ActionList_ actions{};
  actions.header_.stamp_ = stamp;
  actions.header_.frame_id_ = frame_id;
  actions.plan_seq_ = published_ + 1;
  actions.actions_._length = actions.actions_._maximum = static_cast<uint32_t>(acts.size());
  actions.actions_._buffer = acts.data();
  actions.actions_._release = false;
  check(dds_write(actions_writer_, &actions), "publishing actions on " + actions_topic_);
  ++published_;
}

}  // namespace flipper::dds
