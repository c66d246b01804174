#pragma once
// An independent NavigateThroughPoses action server for the tests, written from the ROS 2
// definitions (docs/ros2/interfaces: action_msgs, nav2_msgs, unique_identifier_msgs) and ROS 2's
// DDS naming of actions, not from Flipper's connector: Cyclone's C API on the IDL types only.
// It plays Nav2's part of the action protocol: send_goal -> accepted (or rejected), status
// ACCEPTED then EXECUTING, one feedback, then the goal's end when the test says so (succeeded,
// aborted with an error code) or when a cancel request comes (CANCELING, then CANCELED); the
// get_result reply goes out when the goal has ended. Every request is recorded.
#include <dds/dds.h>

#include <array>
#include <atomic>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "action_msgs/msg/GoalStatus.h"
#include "action_msgs/srv/CancelGoal.h"
#include "nav2_msgs/action/NavigateThroughPoses.h"
#include "nav2_msgs/action/NavigateThroughPosesJazzy.h"

namespace flipper::ddstest {

class Nav2ActionServer {
 public:
  using Uuid = std::array<std::uint8_t, 16>;
  enum Status : std::int8_t {
    kAccepted = 1,
    kExecuting = 2,
    kCanceling = 3,
    kSucceeded = 4,
    kCanceled = 5,
    kAborted = 6
  };
  struct Goal {
    Uuid id{};
    std::vector<std::array<double, 3>> positions;
    std::vector<std::string> frames;
    std::string behavior_tree;
    bool accepted = false;
    std::int8_t status = 0;
    std::uint16_t error_code = 0;
    std::string error_msg;
    bool result_asked = false, result_sent = false;
    std::uint64_t result_guid = 0;
    std::int64_t result_seq = 0;
  };

  /// `action`: e.g. "navigate_through_poses" or "robot1/navigate_through_poses".
  Nav2ActionServer(dds_entity_t participant, const std::string& action, bool jazzy)
      : participant_(participant), jazzy_(jazzy) {
    const std::string base = action + "/_action/";
    dds_qos_t* service = dds_create_qos();
    dds_qset_reliability(service, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(service, DDS_DURABILITY_VOLATILE);
    dds_qset_history(service, DDS_HISTORY_KEEP_LAST, 10);
    dds_qos_t* status = dds_create_qos();
    dds_qset_reliability(status, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(status, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(status, DDS_HISTORY_KEEP_LAST, 1);
    goal_in_ = reader(&nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Request__desc,
                      "rq/" + base + "send_goalRequest", service);
    goal_out_ = writer(&nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Response__desc,
                       "rr/" + base + "send_goalReply", service);
    result_in_ = reader(&nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Request__desc,
                        "rq/" + base + "get_resultRequest", service);
    // Jazzy's reply layout under ROS 2's one type name for both distributions.
    static const dds_topic_descriptor_t& j =
        nav2_msgs_action_jazzy_dds__NavigateThroughPoses_GetResult_Response__desc;
    static const dds_topic_descriptor_t jazzy_reply{
        j.m_size,
        j.m_align,
        j.m_flagset,
        j.m_nkeys,
        "nav2_msgs::action::dds_::NavigateThroughPoses_GetResult_Response_",
        j.m_keys,
        j.m_nops,
        j.m_ops,
        j.m_meta,
        j.type_information,
        j.type_mapping,
        j.restrict_data_representation};
    result_out_ = writer(
        jazzy ? &jazzy_reply : &nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Response__desc,
        "rr/" + base + "get_resultReply", service);
    cancel_in_ = reader(&action_msgs_srv_dds__CancelGoal_Request__desc,
                        "rq/" + base + "cancel_goalRequest", service);
    cancel_out_ = writer(&action_msgs_srv_dds__CancelGoal_Response__desc,
                         "rr/" + base + "cancel_goalReply", service);
    feedback_out_ = writer(&nav2_msgs_action_dds__NavigateThroughPoses_FeedbackMessage__desc,
                           "rt/" + base + "feedback", service);
    status_out_ =
        writer(&action_msgs_msg_dds__GoalStatusArray__desc, "rt/" + base + "status", status);
    dds_delete_qos(service);
    dds_delete_qos(status);
    thread_ = std::thread([this] {
      while (!stop_) {
        serve();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));  // polling, not a wait
      }
    });
  }
  ~Nav2ActionServer() {
    stop_ = true;
    thread_.join();
    for (dds_entity_t e : entities_) dds_delete(e);
  }
  Nav2ActionServer(const Nav2ActionServer&) = delete;
  Nav2ActionServer& operator=(const Nav2ActionServer&) = delete;

  /// Refuse (true) or accept (false) the goals that come next.
  void reject_next(bool reject) { reject_.store(reject); }
  /// Ends goal number `index` (0-based, in arrival order) with `status` (kSucceeded, kAborted).
  void finish(std::size_t index, std::int8_t status, std::uint16_t error_code = 0,
              const std::string& error_msg = "") {
    std::lock_guard lock(mutex_);
    Goal& g = goals_.at(index);
    g.status = status;
    g.error_code = error_code;
    g.error_msg = error_msg;
    publish_status();
    reply_results();
  }
  std::vector<Goal> goals() const {
    std::lock_guard lock(mutex_);
    return goals_;
  }
  /// The goal ids of the cancel requests received, in order.
  std::vector<Uuid> cancels() const {
    std::lock_guard lock(mutex_);
    return cancels_;
  }

 private:
  dds_entity_t reader(const dds_topic_descriptor_t* d, const std::string& name, dds_qos_t* q) {
    const dds_entity_t t = dds_create_topic(participant_, d, name.c_str(), nullptr, nullptr);
    const dds_entity_t r = dds_create_reader(participant_, t, q, nullptr);
    if (t < 0 || r < 0) throw std::runtime_error("test server: reader on " + name);
    entities_.push_back(r);
    return r;
  }
  dds_entity_t writer(const dds_topic_descriptor_t* d, const std::string& name, dds_qos_t* q) {
    const dds_entity_t t = dds_create_topic(participant_, d, name.c_str(), nullptr, nullptr);
    const dds_entity_t w = dds_create_writer(participant_, t, q, nullptr);
    if (t < 0 || w < 0) throw std::runtime_error("test server: writer on " + name);
    entities_.push_back(w);
    return w;
  }
  template <class T, class F>
  static void each(dds_entity_t r, F&& f) {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    for (;;) {
      const dds_return_t n = dds_take(r, samples, infos, 8, 8);
      if (n <= 0) return;
      for (int i = 0; i < n; ++i)
        if (infos[i].valid_data) f(*static_cast<const T*>(samples[i]));
      dds_return_loan(r, samples, n);
    }
  }
  Goal* find(const std::uint8_t* id) {
    for (Goal& g : goals_)
      if (std::memcmp(g.id.data(), id, 16) == 0) return &g;
    return nullptr;
  }
  static bool ended(const Goal& g) {
    return g.status == kSucceeded || g.status == kCanceled || g.status == kAborted;
  }

  void serve() {
    std::lock_guard lock(mutex_);
    each<nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Request_>(goal_in_, [&](const auto&
                                                                                         r) {
      Goal g;
      std::memcpy(g.id.data(), r.goal_id_.bytes, 16);
      for (uint32_t i = 0; i < r.goal_.poses_._length; ++i) {
        const auto& p = r.goal_.poses_._buffer[i];
        g.positions.push_back({p.pose_.position_.x_, p.pose_.position_.y_, p.pose_.position_.z_});
        g.frames.emplace_back(p.header_.frame_id_);
      }
      g.behavior_tree = r.goal_.behavior_tree_;
      g.accepted = !reject_.load();
      nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Response_ a{};
      a.header_guid = r.header_guid;
      a.header_seq = r.header_seq;
      a.accepted_ = g.accepted;
      a.stamp_.sec_ = 1;
      g.status = g.accepted ? kExecuting : 0;
      goals_.push_back(g);
      dds_write(goal_out_, &a);
      if (!g.accepted) return;
      publish_status();
      nav2_msgs_action_dds__NavigateThroughPoses_FeedbackMessage_ f{};
      std::memcpy(f.goal_id_.bytes, g.id.data(), 16);
      char map[] = "map";
      f.feedback_.current_pose_.header_.frame_id_ = map;
      f.feedback_.number_of_poses_remaining_ = static_cast<int16_t>(g.positions.size());
      f.feedback_.distance_remaining_ = 2.5F;
      f.feedback_.number_of_recoveries_ = 1;
      dds_write(feedback_out_, &f);
    });
    each<nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Request_>(
        result_in_, [&](const auto& r) {
          if (Goal* g = find(r.goal_id_.bytes)) {
            g->result_asked = true;
            g->result_guid = r.header_guid;
            g->result_seq = r.header_seq;
          }
        });
    each<action_msgs_srv_dds__CancelGoal_Request_>(cancel_in_, [&](const auto& r) {
      Uuid id{};
      std::memcpy(id.data(), r.goal_info_.goal_id_.bytes, 16);
      cancels_.push_back(id);
      Goal* g = find(id.data());
      action_msgs_srv_dds__CancelGoal_Response_ a{};
      a.header_guid = r.header_guid;
      a.header_seq = r.header_seq;
      action_msgs_msg_dds__GoalInfo_ info{};
      if (g == nullptr) {
        a.return_code_ = 2;  // ERROR_UNKNOWN_GOAL_ID
      } else if (ended(*g)) {
        a.return_code_ = 3;  // ERROR_GOAL_TERMINATED
      } else {
        a.return_code_ = 0;
        info.goal_id_ = r.goal_info_.goal_id_;
        a.goals_canceling_._length = a.goals_canceling_._maximum = 1;
        a.goals_canceling_._buffer = &info;
        g->status = kCanceling;
        publish_status();
        g->status = kCanceled;  // this server stops at once
      }
      dds_write(cancel_out_, &a);
    });
    publish_status();
    reply_results();
  }

  void publish_status() {
    std::vector<action_msgs_msg_dds__GoalStatus_> list;
    std::vector<std::pair<Uuid, std::int8_t>> shown;
    for (const Goal& g : goals_)
      if (g.accepted) {
        action_msgs_msg_dds__GoalStatus_ s{};
        std::memcpy(s.goal_info_.goal_id_.bytes, g.id.data(), 16);
        s.status_ = g.status;
        list.push_back(s);
        shown.emplace_back(g.id, g.status);
      }
    action_msgs_msg_dds__GoalStatusArray_ a{};
    a.status_list_._length = a.status_list_._maximum = static_cast<uint32_t>(list.size());
    a.status_list_._buffer = list.data();
    if (shown != last_status_) dds_write(status_out_, &a);
    last_status_ = shown;
  }

  void reply_results() {
    for (Goal& g : goals_) {
      if (!g.result_asked || g.result_sent || !ended(g)) continue;
      if (jazzy_) {
        nav2_msgs_action_jazzy_dds__NavigateThroughPoses_GetResult_Response_ a{};
        a.header_guid = g.result_guid;
        a.header_seq = g.result_seq;
        a.status_ = g.status;
        a.result_.error_code_ = g.error_code;
        a.result_.error_msg_ = g.error_msg.data();
        dds_write(result_out_, &a);
      } else {
        nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Response_ a{};
        a.header_guid = g.result_guid;
        a.header_seq = g.result_seq;
        a.status_ = g.status;
        dds_write(result_out_, &a);
      }
      g.result_sent = true;
    }
  }

  dds_entity_t participant_;
  bool jazzy_;
  std::vector<dds_entity_t> entities_;
  dds_entity_t goal_in_, goal_out_, result_in_, result_out_, cancel_in_, cancel_out_, feedback_out_,
      status_out_;
  mutable std::mutex mutex_;
  std::vector<Goal> goals_;
  std::vector<Uuid> cancels_;
  std::vector<std::pair<Uuid, std::int8_t>> last_status_;
  std::atomic<bool> reject_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace flipper::ddstest
