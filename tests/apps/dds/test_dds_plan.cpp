// Plans out: `flipper session --set publish.plans=dds` publishes the accepted plan of
// `visit room3` on rt/flipper/plan as nav_msgs::msg::dds_::Path_, in metres, and the picks on
// rt/flipper/actions. Expected poses are hand-computed from the study map (below), not read
// back from Flipper.
#include <array>
#include <cmath>
#include <fstream>

#include "dds_test_support.hpp"
#include "flipper/dds/plan_publisher.hpp"
#include "flipper/msg/Actions.h"
#include "nav_msgs/msg/Path.h"

using namespace flipper;
using namespace flipper::ddstest;

TEST_CASE("accepted visit room3 arrives on rt/flipper/plan as a ROS 2 Path in metres", "[dds]") {
  const int kDomain = test_domain();
  auto participant = test_participant(kDomain);
  SampleReader<nav_msgs_msg_dds__Path_> plans(*participant, &nav_msgs_msg_dds__Path__desc,
                                              dds::kPlanTopic);
  SampleReader<flipper_msg_dds__ActionList_> actions(
      *participant, &flipper_msg_dds__ActionList__desc, dds::kActionsTopic);
  // ROS 2's DDS names: what rmw_cyclonedds matches on.
  CHECK(std::string(nav_msgs_msg_dds__Path__desc.m_typename) == "nav_msgs::msg::dds_::Path_");
  CHECK(std::string(dds::kPlanTopic) == "rt/flipper/plan");

  testsupport::ChildProcess session({flipper_bin(), "session", "--set", "publish.plans=dds",
                                     "--set", "dds.domain=" + std::to_string(kDomain), "--set",
                                     "lexicon.path=:memory:", "--set", "world.resolution=0.25",
                                     "--set", "world.origin=[1.5, -2.0]"});
  const auto call = [&](const json& r) {
    REQUIRE(session.write_line(r.dump()));
    return json::parse(session.read_line());
  };
  REQUIRE(call({{"op", "world"}, {"world", study_world_with_robot(10, 7)}})["ok"] == true);
  REQUIRE(call({{"op", "query"}, {"text", "visit room3"}})["ok"] == true);
  REQUIRE(call({{"op", "accept"}, {"rank", 0}})["ok"] == true);

  // Study map: from (10,7) the only way into room3 is the door (9,6): (9,7), (9,6), then (9,5),
  // room3's nearest cell. Metres: x = 1.5 + 0.25 cx, y = -2 + 0.25 cy.
  const std::vector<std::array<double, 3>> expected = {
      {4.0, -0.25, 0}, {3.75, -0.25, 0}, {3.75, -0.5, 0}, {3.75, -0.75, 0}};
  // Yaw faces the next step: left (pi), then down (-pi/2) to the end.
  const double s = std::sqrt(0.5);
  const std::vector<std::array<double, 4>> quats = {
      {0, 0, 1, 0}, {0, 0, -s, s}, {0, 0, -s, s}, {0, 0, -s, s}};
  bool got = plans.next([&](const nav_msgs_msg_dds__Path_& path) {
    CHECK(std::string(path.header_.frame_id_) == "map");
    REQUIRE(path.poses_._length == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
      const auto& p = path.poses_._buffer[i];
      CHECK(p.pose_.position_.x_ == Approx(expected[i][0]).margin(1e-12));
      CHECK(p.pose_.position_.y_ == Approx(expected[i][1]).margin(1e-12));
      CHECK(p.pose_.position_.z_ == Approx(expected[i][2]).margin(1e-12));
      CHECK(p.pose_.orientation_.x_ == Approx(quats[i][0]).margin(1e-12));
      CHECK(p.pose_.orientation_.y_ == Approx(quats[i][1]).margin(1e-12));
      CHECK(std::abs(p.pose_.orientation_.z_) == Approx(std::abs(quats[i][2])).margin(1e-12));
      CHECK(p.pose_.orientation_.z_ * p.pose_.orientation_.w_ ==
            Approx(quats[i][2] * quats[i][3]).margin(1e-12));
      CHECK(std::string(p.header_.frame_id_) == "map");
      CHECK(p.header_.stamp_.sec_ == path.header_.stamp_.sec_);
    }
    CHECK(path.header_.stamp_.sec_ > 1700000000);  // wall clock, like ROS time
  });
  REQUIRE(got);
  got = actions.next([&](const flipper_msg_dds__ActionList_& a) {
    CHECK(a.plan_seq_ == 1);
    CHECK(a.actions_._length == 0);  // a visit picks nothing
  });
  REQUIRE(got);

  // A pick: the blue circle (id 0) lies on (3,8); from (3,7) one step up, then the pick.
  REQUIRE(call({{"op", "world"}, {"world", study_world_with_robot(3, 7)}})["ok"] == true);
  REQUIRE(call({{"op", "query"}, {"text", "move up; pick item is blue"}})["ok"] == true);
  REQUIRE(call({{"op", "accept"}, {"rank", 0}})["ok"] == true);
  got = plans.next([&](const nav_msgs_msg_dds__Path_& path) {
    REQUIRE(path.poses_._length == 2);
    CHECK(path.poses_._buffer[1].pose_.position_.x_ == Approx(2.25).margin(1e-12));
    CHECK(path.poses_._buffer[1].pose_.position_.y_ == Approx(0.0).margin(1e-12));
  });
  REQUIRE(got);
  got = actions.next([&](const flipper_msg_dds__ActionList_& a) {
    CHECK(a.plan_seq_ == 2);
    REQUIRE(a.actions_._length == 1);
    const auto& act = a.actions_._buffer[0];
    CHECK(std::string(act.kind_) == "pick");
    CHECK(act.pose_index_ == 1);
    CHECK(act.position_.x_ == Approx(2.25).margin(1e-12));
    CHECK(act.position_.y_ == Approx(0.0).margin(1e-12));
    CHECK(act.item_id_ == 0);
    CHECK(std::string(act.color_) == "blue");
    CHECK(std::string(act.shape_) == "circle");
  });
  REQUIRE(got);
  CHECK(session.finish() == 0);
}
