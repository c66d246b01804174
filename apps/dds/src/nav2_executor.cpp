#include "flipper/dds/nav2_executor.hpp"

#include <chrono>
#include <cstring>
#include <ostream>
#include <random>

#include "action_msgs/msg/GoalStatus.h"
#include "action_msgs/srv/CancelGoal.h"
#include "flipper/dds/names.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/json/json_writer.hpp"
#include "nav2_msgs/action/NavigateThroughPoses.h"
#include "nav2_msgs/action/NavigateThroughPosesJazzy.h"
#include "ros_time.hpp"

namespace flipper::dds {
namespace {

// action_msgs/msg/GoalStatus
constexpr int kStatusExecuting = 2;
constexpr int kStatusCanceling = 3;
constexpr int kStatusSucceeded = 4;
constexpr int kStatusCanceled = 5;
constexpr int kStatusAborted = 6;

constexpr const char* kResultReplyType =
    "nav2_msgs::action::dds_::NavigateThroughPoses_GetResult_Response_";

// Jazzy's get_result reply under ROS 2's type name (its IDL is compiled in module `jazzy`).
const dds_topic_descriptor_t& jazzy_result_reply() {
  static const dds_topic_descriptor_t& d =
      nav2_msgs_action_jazzy_dds__NavigateThroughPoses_GetResult_Response__desc;
  static const dds_topic_descriptor_t renamed{
      d.m_size,         d.m_align,          d.m_flagset,    d.m_nkeys,
      kResultReplyType, d.m_keys,           d.m_nops,       d.m_ops,
      d.m_meta,         d.type_information, d.type_mapping, d.restrict_data_representation};
  return renamed;
}

std::array<std::uint8_t, 16> random_uuid() {
  static std::mutex m;
  static std::random_device device;
  static std::mt19937_64 bits(device());
  std::lock_guard lock(m);
  std::array<std::uint8_t, 16> id{};
  for (std::size_t i = 0; i < id.size(); i += 8) {
    const std::uint64_t r = bits();
    std::memcpy(id.data() + i, &r, 8);
  }
  id[6] = static_cast<std::uint8_t>((id[6] & 0x0f) | 0x40);  // RFC 4122 version 4
  id[8] = static_cast<std::uint8_t>((id[8] & 0x3f) | 0x80);
  return id;
}

// Takes every sample of `reader` and calls `f` on the valid ones.
template <class T, class F>
void take_all(dds_entity_t reader, F&& f) {
  constexpr int kBatch = 16;
  for (;;) {
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    for (int i = 0; i < n; ++i)
      if (infos[i].valid_data) f(*static_cast<const T*>(samples[i]));
    dds_return_loan(reader, samples, n);
    if (n < kBatch) return;
  }
}

dds_entity_t make_reader(Participant& p, const dds_topic_descriptor_t* d, const std::string& name,
                         const Qos& qos) {
  return check(dds_create_reader(p.handle(), p.topic(d, name), qos.q, nullptr),
               "creating a reader on " + name);
}
dds_entity_t make_writer(Participant& p, const dds_topic_descriptor_t* d, const std::string& name,
                         const Qos& qos) {
  return check(dds_create_writer(p.handle(), p.topic(d, name), qos.q, nullptr),
               "creating a writer on " + name);
}

std::uint64_t instance_of(dds_entity_t e) {
  dds_instance_handle_t h = 0;
  check(dds_get_instance_handle(e, &h), "reading a writer's instance handle");
  return h;
}

}  // namespace

bool Nav2Goal::terminal() const {
  return state == "succeeded" || state == "aborted" || state == "rejected" ||
         state == "cancelled" || state == "dropped" || state == "unknown";
}

Nav2Executor::Options Nav2Executor::options_from_config(const kernel::Config& config) {
  Options o;
  o.ns = config.get(keys::kNamespace);
  o.action = config.get(keys::kNav2Action);
  o.distro = config.get(keys::kNav2Distro);
  o.behavior_tree = config.get(keys::kNav2BehaviorTree);
  // The action's name is ROS 2 name tokens joined by '/' (a sub-namespace may come first).
  const std::string key(keys::kNav2Action.name);
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = o.action.find('/', start);
    const std::string token = o.action.substr(start, end - start);
    if (token.empty())
      throw sdk::Error(sdk::codes::kBadConfig,
                       key + " '" + o.action.substr(0, 64) + "' has an empty name token");
    check_namespace(token, key);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return o;
}

Nav2Executor::Nav2Executor(std::shared_ptr<Participant> participant, PlanFrame frame,
                           Options options, std::ostream& log)
    : participant_(std::move(participant)),
      frame_(std::move(frame)),
      options_(std::move(options)),
      log_(log),
      prefix_(dds::action_prefix(options_.ns, options_.action)) {
  auto& p = *participant_;
  Qos service;  // rmw's services: reliable, volatile, keep-last 10
  ros_default_qos(service, 10);
  Qos status;  // rcl_action's status: reliable, transient-local
  latched_qos(status);
  const std::string rq = "rq/" + prefix_, rr = "rr/" + prefix_, rt = "rt/" + prefix_;
  goal_writer_ = make_writer(p, &nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Request__desc,
                             rq + "send_goalRequest", service);
  goal_reader_ = make_reader(p, &nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Response__desc,
                             rr + "send_goalReply", service);
  result_writer_ =
      make_writer(p, &nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Request__desc,
                  rq + "get_resultRequest", service);
  result_reader_ =
      make_reader(p,
                  options_.distro == keys::Nav2Distro::jazzy
                      ? &jazzy_result_reply()
                      : &nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Response__desc,
                  rr + "get_resultReply", service);
  cancel_writer_ = make_writer(p, &action_msgs_srv_dds__CancelGoal_Request__desc,
                               rq + "cancel_goalRequest", service);
  cancel_reader_ = make_reader(p, &action_msgs_srv_dds__CancelGoal_Response__desc,
                               rr + "cancel_goalReply", service);
  feedback_reader_ =
      make_reader(p, &nav2_msgs_action_dds__NavigateThroughPoses_FeedbackMessage__desc,
                  rt + "feedback", service);
  status_reader_ =
      make_reader(p, &action_msgs_msg_dds__GoalStatusArray__desc, rt + "status", status);
  goal_guid_ = instance_of(goal_writer_);
  result_guid_ = instance_of(result_writer_);
  cancel_guid_ = instance_of(cancel_writer_);

  waitset_ = check(dds_create_waitset(p.handle()), "creating the Nav2 waitset");
  wake_ = check(dds_create_guardcondition(p.handle()), "creating the Nav2 guard condition");
  check(dds_waitset_attach(waitset_, wake_, 0), "attaching the guard condition");
  for (dds_entity_t r :
       {goal_reader_, result_reader_, cancel_reader_, feedback_reader_, status_reader_}) {
    check(dds_set_status_mask(r, DDS_DATA_AVAILABLE_STATUS), "reader status mask");
    check(dds_waitset_attach(waitset_, r, r), "attaching a Nav2 reader");
  }
  log_ << "flipper: Nav2 executor: NavigateThroughPoses ("
       << (options_.distro == keys::Nav2Distro::jazzy ? "jazzy" : "humble") << ") at rq/" << prefix_
       << "send_goalRequest\n";
  worker_ = std::thread([this] { run(); });
}

Nav2Executor::~Nav2Executor() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  dds_set_guardcondition(wake_, true);
  if (worker_.joinable()) worker_.join();
  for (dds_entity_t e :
       {waitset_, wake_, goal_writer_, goal_reader_, result_writer_, result_reader_, cancel_writer_,
        cancel_reader_, feedback_reader_, status_reader_})
    if (e > 0) dds_delete(e);
}

void Nav2Executor::attach(kernel::Session& session) {
  const void* self = &session;
  session.on<kernel::PlanAccepted>([this, self](const kernel::PlanAccepted& plan) {
    std::vector<Pose> poses = frame_.poses(plan.before.robot, plan.outcome.trace);
    if (!poses.empty()) poses.erase(poses.begin());  // the robot is at pose 0 already
    submit(std::move(poses), plan.sequence, self);
  });
  session.on<kernel::WorldReplaced>(
      [this](const kernel::WorldReplaced& w) { cancel_session_goal(&w.session); });
  session.set_op(
      "execution", [this](kernel::Session&, const kernel::Json&, toolkit::json::JsonWriter& a) {
        a.key("goals").begin_array();
        for (const Nav2Goal& g : goals()) {
          a.begin_object();
          a.key("goal").unsigned_integer(g.number).key("plan").unsigned_integer(g.plan);
          a.key("state").string(g.state).key("poses").unsigned_integer(g.poses.size());
          a.key("feedbacks").unsigned_integer(g.feedbacks);
          if (g.feedbacks > 0)
            a.key("poses_remaining")
                .integer(g.poses_remaining)
                .key("distance_remaining")
                .number(g.distance_remaining)
                .key("recoveries")
                .integer(g.recoveries);
          if (g.state == "aborted" && options_.distro == keys::Nav2Distro::jazzy)
            a.key("error_code").integer(g.error_code).key("error_msg").string(g.error_msg);
          a.end_object();
        }
        a.end_array();
      });
}

std::vector<Nav2Goal> Nav2Executor::goals() const {
  std::lock_guard lock(mutex_);
  return {goals_.begin(), goals_.end()};
}

void Nav2Executor::set_state(Nav2Goal& goal, const std::string& state) {
  if (goal.state == state) return;
  goal.state = state;
  log_ << "flipper: Nav2 goal " << goal.number << " (plan " << goal.plan << "): " << state;
  if (state == "aborted" && options_.distro == keys::Nav2Distro::jazzy)
    log_ << " (error_code " << goal.error_code << ": " << goal.error_msg << ")";
  log_ << "\n";
}

// A new plan replaces the robot's current one: the goal before is cancelled (or dropped when it
// was never sent).
void Nav2Executor::submit(std::vector<Pose> poses, std::uint64_t plan, const void* session) {
  std::lock_guard lock(mutex_);
  for (Nav2Goal& g : goals_)
    if (!g.terminal()) {
      if (g.state == "waiting_for_server")
        set_state(g, "dropped");
      else
        g.cancel_wanted = true;
    }
  Nav2Goal goal;
  goal.number = next_number_++;
  goal.plan = plan;
  goal.uuid = random_uuid();
  goal.poses = std::move(poses);
  goal.session = session;
  log_ << "flipper: Nav2 goal " << goal.number << " (plan " << plan << "): " << goal.poses.size()
       << " poses\n";
  if (goal.poses.empty()) goal.state = "dropped";  // nothing to drive: Nav2 refuses no poses
  goals_.push_back(std::move(goal));
  while (goals_.size() > kKept && goals_.front().terminal()) goals_.pop_front();
  dds_set_guardcondition(wake_, true);
}

void Nav2Executor::cancel_session_goal(const void* session) {
  std::lock_guard lock(mutex_);
  for (Nav2Goal& g : goals_)
    if (g.session == session && !g.terminal()) {
      if (g.state == "waiting_for_server")
        set_state(g, "dropped");
      else
        g.cancel_wanted = true;
    }
  dds_set_guardcondition(wake_, true);
}

void Nav2Executor::run() {
  constexpr dds_duration_t kPoll = DDS_MSECS(100);  // also notices a server that appears
  for (;;) {
    dds_waitset_wait(waitset_, nullptr, 0, kPoll);
    dds_set_guardcondition(wake_, false);
    std::lock_guard lock(mutex_);
    if (stop_) return;
    try {
      step();
    } catch (const std::exception& e) {
      log_ << "flipper: Nav2 executor: " << e.what() << "\n";
    }
  }
}

bool Nav2Executor::server_matched() const {
  dds_publication_matched_status_t pub{};
  dds_subscription_matched_status_t sub{};
  dds_get_publication_matched_status(goal_writer_, &pub);
  dds_get_subscription_matched_status(goal_reader_, &sub);
  return pub.current_count > 0 && sub.current_count > 0;
}

void Nav2Executor::step() {
  take_goal_replies();
  take_feedback();
  take_status();
  take_result_replies();
  take_cancel_replies();
  for (Nav2Goal& g : goals_) {
    if (g.state == "waiting_for_server" && server_matched()) send_goal(g);
    if (g.cancel_wanted && !g.cancel_sent && !g.terminal() && g.state != "sent") send_cancel(g);
  }
}

void Nav2Executor::send_goal(Nav2Goal& goal) {
  const auto stamp = now_stamp();
  char frame_id[] = "map";
  std::vector<geometry_msgs_msg_dds__PoseStamped_> stamped(goal.poses.size());
  for (std::size_t i = 0; i < goal.poses.size(); ++i) {
    auto& s = stamped[i];
    s.header_.stamp_ = stamp;
    s.header_.frame_id_ = frame_id;
    const Pose& p = goal.poses[i];
    s.pose_.position_ = {p.position.x(), p.position.y(), p.position.z()};
    s.pose_.orientation_ = {p.orientation.x(), p.orientation.y(), p.orientation.z(),
                            p.orientation.w()};
  }
  std::string tree = options_.behavior_tree;
  nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Request_ r{};
  r.header_guid = goal_guid_;
  r.header_seq = goal.request_seq = next_seq_++;
  std::memcpy(r.goal_id_.bytes, goal.uuid.data(), goal.uuid.size());
  r.goal_.poses_._length = r.goal_.poses_._maximum = static_cast<uint32_t>(stamped.size());
  r.goal_.poses_._buffer = stamped.data();
  r.goal_.poses_._release = false;
  r.goal_.behavior_tree_ = tree.data();
  check(dds_write(goal_writer_, &r), "sending a NavigateThroughPoses goal");
  set_state(goal, "sent");
}

void Nav2Executor::send_result_request(Nav2Goal& goal) {
  nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Request_ r{};
  r.header_guid = result_guid_;
  r.header_seq = goal.result_seq = next_seq_++;
  std::memcpy(r.goal_id_.bytes, goal.uuid.data(), goal.uuid.size());
  check(dds_write(result_writer_, &r), "asking Nav2 for a goal's result");
}

void Nav2Executor::send_cancel(Nav2Goal& goal) {
  action_msgs_srv_dds__CancelGoal_Request_ r{};
  r.header_guid = cancel_guid_;
  r.header_seq = next_seq_++;
  std::memcpy(r.goal_info_.goal_id_.bytes, goal.uuid.data(), goal.uuid.size());
  // stamp zero: this goal only (action_msgs/srv/CancelGoal)
  check(dds_write(cancel_writer_, &r), "cancelling a Nav2 goal");
  goal.cancel_sent = true;
  set_state(goal, "canceling");
}

Nav2Goal* Nav2Executor::find(const std::uint8_t* uuid) {
  for (Nav2Goal& g : goals_)
    if (std::memcmp(g.uuid.data(), uuid, g.uuid.size()) == 0) return &g;
  return nullptr;
}

void Nav2Executor::take_goal_replies() {
  take_all<nav2_msgs_action_dds__NavigateThroughPoses_SendGoal_Response_>(
      goal_reader_, [&](const auto& r) {
        if (r.header_guid != goal_guid_) return;  // another client's reply
        for (Nav2Goal& g : goals_)
          if (g.state == "sent" && g.request_seq == r.header_seq) {
            if (!r.accepted_) {
              set_state(g, "rejected");
            } else {
              set_state(g, "accepted");
              send_result_request(g);
            }
          }
      });
}

void Nav2Executor::take_feedback() {
  take_all<nav2_msgs_action_dds__NavigateThroughPoses_FeedbackMessage_>(
      feedback_reader_, [&](const auto& m) {
        Nav2Goal* g = find(m.goal_id_.bytes);
        if (g == nullptr || g->terminal()) return;
        ++g->feedbacks;
        g->poses_remaining = m.feedback_.number_of_poses_remaining_;
        g->distance_remaining = m.feedback_.distance_remaining_;
        g->recoveries = m.feedback_.number_of_recoveries_;
        if (g->state == "accepted") set_state(*g, "executing");
      });
}

void Nav2Executor::take_status() {
  take_all<action_msgs_msg_dds__GoalStatusArray_>(status_reader_, [&](const auto& a) {
    for (uint32_t i = 0; i < a.status_list_._length; ++i) {
      const auto& s = a.status_list_._buffer[i];
      Nav2Goal* g = find(s.goal_info_.goal_id_.bytes);
      if (g == nullptr || g->terminal()) continue;
      if (s.status_ == kStatusExecuting && g->state == "accepted") set_state(*g, "executing");
      if (s.status_ == kStatusCanceling) set_state(*g, "canceling");
    }
  });
}

void Nav2Executor::take_result_replies() {
  const auto finish = [&](std::int64_t seq, int status, int error_code, const char* error_msg) {
    for (Nav2Goal& g : goals_)
      if (g.result_seq == seq && !g.terminal()) {
        g.error_code = error_code;
        g.error_msg = error_msg;
        set_state(g, status == kStatusSucceeded  ? "succeeded"
                     : status == kStatusAborted  ? "aborted"
                     : status == kStatusCanceled ? "cancelled"
                                                 : "unknown");
      }
  };
  if (options_.distro == keys::Nav2Distro::jazzy)
    take_all<nav2_msgs_action_jazzy_dds__NavigateThroughPoses_GetResult_Response_>(
        result_reader_, [&](const auto& r) {
          if (r.header_guid == result_guid_)
            finish(r.header_seq, r.status_, r.result_.error_code_,
                   r.result_.error_msg_ != nullptr ? r.result_.error_msg_ : "");
        });
  else
    take_all<nav2_msgs_action_dds__NavigateThroughPoses_GetResult_Response_>(
        result_reader_, [&](const auto& r) {
          if (r.header_guid == result_guid_) finish(r.header_seq, r.status_, 0, "");
        });
}

void Nav2Executor::take_cancel_replies() {
  take_all<action_msgs_srv_dds__CancelGoal_Response_>(cancel_reader_, [&](const auto& r) {
    if (r.header_guid != cancel_guid_) return;
    for (uint32_t i = 0; i < r.goals_canceling_._length; ++i)
      if (Nav2Goal* g = find(r.goals_canceling_._buffer[i].goal_id_.bytes))
        g->cancel_return_code = r.return_code_;
    if (r.return_code_ != 0)
      log_ << "flipper: Nav2 refused a cancel (return_code " << static_cast<int>(r.return_code_)
           << ")\n";
  });
}

}  // namespace flipper::dds
