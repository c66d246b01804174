#pragma once
/// @file nav2_executor.hpp
/// `nav2.execute: true`: Nav2 drives the robot. Every accepted plan (the session's PlanAccepted
/// event, and nothing else) is sent as a nav2_msgs/action/NavigateThroughPoses goal over ROS 2's
/// action protocol on Cyclone DDS (docs/ros2.md "Nav2 as the executor"): the send_goal,
/// get_result and cancel_goal services (rq/<ns>/<action>/_action/...Request, rr/...Reply,
/// reliable, volatile, keep-last 10) and the feedback (reliable, volatile) and status
/// (reliable, transient-local) topics. The robot runs one plan at a time: a new accepted plan
/// cancels the goal before it, and so does the world of the session whose plan runs being
/// replaced (an undo, a `world` request). The session's `execution` op reports the goals:
/// waiting_for_server, sent, accepted, executing, canceling, then succeeded, aborted (with Nav2's
/// error code on Jazzy), rejected, cancelled or dropped (cancelled before it was sent).

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "flipper/dds/config_keys.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/dds/plan_frame.hpp"
#include "flipper/kernel/session.hpp"

namespace flipper::dds {

/// One goal as the session sees it.
struct Nav2Goal {
  std::uint64_t number = 0;  ///< 1, 2, ...: goals of this executor
  std::uint64_t plan = 0;    ///< the accepting session's plan sequence (PlanAccepted::sequence)
  std::array<std::uint8_t, 16> uuid{};
  std::string state = "waiting_for_server";
  std::vector<Pose> poses;        ///< the waypoints: every cell the plan enters, in metres
  const void* session = nullptr;  ///< the accepting session (compared, never dereferenced)
  std::int64_t request_seq = 0;   ///< send_goal's sequence number
  std::int64_t result_seq = 0;    ///< get_result's
  bool cancel_wanted = false;     ///< cancel once the server accepted it
  bool cancel_sent = false;
  int cancel_return_code = -1;  ///< CancelGoal's return_code, -1: no reply yet
  int error_code = 0;           ///< Jazzy's result error_code (0: NONE)
  std::string error_msg;        ///< Jazzy's result error_msg
  std::uint64_t feedbacks = 0;
  int poses_remaining = -1;  ///< the last feedback's number_of_poses_remaining
  double distance_remaining = 0;
  int recoveries = 0;

  bool terminal() const;
};

class Nav2Executor : public kernel::SessionExtension {
 public:
  struct Options {
    std::string ns;  ///< dds.namespace
    std::string action = "navigate_through_poses";
    keys::Nav2Distro distro = keys::Nav2Distro::humble;
    std::string behavior_tree;
  };
  static Options options_from_config(const kernel::Config& config);

  Nav2Executor(std::shared_ptr<Participant> participant, PlanFrame frame, Options options,
               std::ostream& log);
  ~Nav2Executor() override;
  Nav2Executor(const Nav2Executor&) = delete;
  Nav2Executor& operator=(const Nav2Executor&) = delete;

  /// PlanAccepted -> a goal; WorldReplaced -> cancel that session's goal; op `execution`.
  void attach(kernel::Session& session) override;
  /// The last goals (at most kKept), oldest first.
  std::vector<Nav2Goal> goals() const;
  /// "rq/<ns>/<action>/_action/" without the service: where the action lives.
  const std::string& action_prefix() const { return prefix_; }

  static constexpr std::size_t kKept = 16;

 private:
  void submit(std::vector<Pose> poses, std::uint64_t plan, const void* session);
  void cancel_session_goal(const void* session);
  void run();
  void step();  // under mutex_
  void send_goal(Nav2Goal& goal);
  void send_result_request(Nav2Goal& goal);
  void send_cancel(Nav2Goal& goal);
  void take_goal_replies();
  void take_result_replies();
  void take_cancel_replies();
  void take_feedback();
  void take_status();
  void set_state(Nav2Goal& goal, const std::string& state);
  Nav2Goal* find(const std::uint8_t* uuid);
  bool server_matched() const;

  std::shared_ptr<Participant> participant_;
  PlanFrame frame_;
  Options options_;
  std::ostream& log_;
  std::string prefix_;
  mutable std::mutex mutex_;
  std::deque<Nav2Goal> goals_;
  std::uint64_t next_number_ = 1;
  std::int64_t next_seq_ = 1;
  dds_entity_t goal_writer_ = 0, goal_reader_ = 0;
  dds_entity_t result_writer_ = 0, result_reader_ = 0;
  dds_entity_t cancel_writer_ = 0, cancel_reader_ = 0;
  dds_entity_t feedback_reader_ = 0, status_reader_ = 0;
  dds_entity_t waitset_ = 0, wake_ = 0;
  std::uint64_t goal_guid_ = 0, result_guid_ = 0, cancel_guid_ = 0;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace flipper::dds
