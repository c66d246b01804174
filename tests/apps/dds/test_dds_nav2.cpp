// Nav2 as the executor (docs/ros2.md "Nav2 as the executor"): `flipper session --set
// nav2.execute=true` sends each accepted plan as a NavigateThroughPoses goal to an independent
// action server (nav2_action_server.hpp, written from the ROS 2 definitions) and reports what
// Nav2 says through the session's `execution` op. Expected waypoints are hand-computed from the
// study map (as in test_dds_plan), not read back from Flipper. Every wait is on a condition,
// bounded by wait_until.
#include "dds_test_support.hpp"
#include "nav2_action_server.hpp"

using namespace flipper;
using namespace flipper::ddstest;

namespace {

struct Robot {
  std::unique_ptr<testsupport::ChildProcess> child;
  Robot(int domain, const std::string& distro, const std::string& ns = "") {
    ensure_loopback_env();
    std::vector<std::string> args = {flipper_bin(), "session",
                                     "--set",       "nav2.execute=true",
                                     "--set",       "nav2.distro=" + distro,
                                     "--set",       "nav2.behavior_tree=bt.xml",
                                     "--set",       "dds.domain=" + std::to_string(domain),
                                     "--set",       "lexicon.path=:memory:",
                                     "--set",       "world.resolution=0.25",
                                     "--set",       "world.origin=[1.5, -2.0]"};
    if (!ns.empty()) args.insert(args.end(), {"--set", "dds.namespace=" + ns});
    child = std::make_unique<testsupport::ChildProcess>(args);
  }
  json call(const json& r) {
    REQUIRE(child->write_line(r.dump()));
    const std::string line = child->read_line(std::chrono::seconds(30));
    REQUIRE_FALSE(line.empty());
    return json::parse(line);
  }
  void world(int x, int y) {
    REQUIRE(call({{"op", "world"}, {"world", study_world_with_robot(x, y)}})["ok"] == true);
  }
  void query(const std::string& text) {
    const json a = call({{"op", "query"}, {"text", text}});
    REQUIRE(a["ok"] == true);
    REQUIRE_FALSE(a["candidates"].empty());
  }
  void accept() { REQUIRE(call({{"op", "accept"}, {"rank", 0}})["ok"] == true); }
  json goals() {
    const json a = call({{"op", "execution"}});
    REQUIRE(a["ok"] == true);
    return a["goals"];
  }
  /// Waits until goal `n` (1-based) is in `state`; returns the goal.
  json wait_state(std::size_t n, const std::string& state) {
    json last;
    const bool ok = wait_until([&] {
      last = goals();
      return last.size() >= n && last[n - 1]["state"] == state;
    });
    INFO("goals: " << last.dump());
    REQUIRE(ok);
    return last[n - 1];
  }
};

std::size_t goal_count(const Nav2ActionServer& s) {
  return s.goals().size();
}

}  // namespace

TEST_CASE(
    "an accepted plan runs on Nav2 (accept then executing with feedback then succeeded) and "
    "an unaccepted plan is never sent",
    "[dds][nav2]") {
  const int kDomain = test_domain();
  auto participant = test_participant(kDomain);
  Nav2ActionServer nav2(participant->handle(), "navigate_through_poses", false);
  Robot robot(kDomain, "humble");
  robot.world(10, 7);
  robot.query("visit room3");
  robot.accept();
  REQUIRE(wait_until([&] { return goal_count(nav2) >= 1; }));
  auto goals = nav2.goals();
  REQUIRE(goals.size() == 1);
  // visit room3 from (10,7): (9,7), (9,6), (9,5); metres x = 1.5 + 0.25 cx, y = -2 + 0.25 cy.
  const std::vector<std::array<double, 3>> expected = {
      {3.75, -0.25, 0}, {3.75, -0.5, 0}, {3.75, -0.75, 0}};
  REQUIRE(goals[0].positions.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k)
      CHECK(goals[0].positions[i][k] == Approx(expected[i][k]).margin(1e-12));
  for (const auto& f : goals[0].frames) CHECK(f == "map");
  CHECK(goals[0].behavior_tree == "bt.xml");

  const json executing = robot.wait_state(1, "executing");
  CHECK(executing["plan"] == 1);
  CHECK(executing["poses"] == 3);
  CHECK(executing["feedbacks"] == 1);
  CHECK(executing["poses_remaining"] == 3);
  CHECK(executing["distance_remaining"] == 2.5);
  CHECK(executing["recoveries"] == 1);
  nav2.finish(0, Nav2ActionServer::kSucceeded);
  robot.wait_state(1, "succeeded");

  // The server is matched now (goal 1 went through): a plan shown and not accepted would reach
  // it before the next accepted one.
  robot.query("move left");  // (9,5) -> (8,5): shown, never accepted
  robot.query("move right");
  robot.accept();  // (9,5) -> (10,5)
  REQUIRE(wait_until([&] { return goal_count(nav2) >= 2; }));
  goals = nav2.goals();
  REQUIRE(goals.size() == 2);
  REQUIRE(goals[1].positions.size() == 1);
  CHECK(goals[1].positions[0][0] == Approx(4.0).margin(1e-12));
  CHECK(goals[1].positions[0][1] == Approx(-0.75).margin(1e-12));
  nav2.finish(1, Nav2ActionServer::kSucceeded);
  CHECK(robot.wait_state(2, "succeeded")["plan"] == 2);
  CHECK(goal_count(nav2) == 2);
  CHECK(nav2.cancels().empty());
  CHECK(robot.child->finish() == 0);
}

TEST_CASE("a goal Nav2 rejects is reported rejected", "[dds][nav2]") {
  const int kDomain = test_domain();
  auto participant = test_participant(kDomain);
  Nav2ActionServer nav2(participant->handle(), "robot1/navigate_through_poses", false);
  nav2.reject_next(true);
  Robot robot(kDomain, "humble", "robot1");  // the action lives under the robot's namespace
  robot.world(10, 7);
  robot.query("visit room3");
  robot.accept();
  const json g = robot.wait_state(1, "rejected");
  CHECK(g["feedbacks"] == 0);
  REQUIRE(goal_count(nav2) == 1);
  CHECK_FALSE(nav2.goals()[0].accepted);
  CHECK(robot.child->finish() == 0);
}

TEST_CASE("Jazzy: an aborted goal is reported with Nav2's error code", "[dds][nav2]") {
  const int kDomain = test_domain();
  auto participant = test_participant(kDomain);
  Nav2ActionServer nav2(participant->handle(), "navigate_through_poses", true);
  Robot robot(kDomain, "jazzy");
  robot.world(10, 7);
  robot.query("visit room3");
  robot.accept();
  robot.wait_state(1, "executing");
  nav2.finish(0, Nav2ActionServer::kAborted, 305, "no valid path");
  const json g = robot.wait_state(1, "aborted");
  CHECK(g["error_code"] == 305);
  CHECK(g["error_msg"] == "no valid path");
  CHECK(robot.child->finish() == 0);  // a clean exit: the server's writers need not linger
}

TEST_CASE("a new plan cancels the running goal and an undo cancels it too", "[dds][nav2]") {
  const int kDomain = test_domain();
  auto participant = test_participant(kDomain);
  Nav2ActionServer nav2(participant->handle(), "navigate_through_poses", false);
  Robot robot(kDomain, "humble");
  robot.world(10, 7);
  robot.query("visit room3");
  robot.accept();
  robot.wait_state(1, "executing");
  // A new accepted plan: goal 1 is cancelled, goal 2 runs.
  robot.query("move right");
  robot.accept();
  robot.wait_state(1, "cancelled");
  robot.wait_state(2, "executing");
  auto goals = nav2.goals();
  REQUIRE(goals.size() == 2);
  REQUIRE(nav2.cancels().size() == 1);
  CHECK(nav2.cancels()[0] == goals[0].id);
  REQUIRE(goals[1].positions.size() == 1);  // (10,5) after visit room3's (9,5): one step right
  CHECK(goals[1].positions[0][0] == Approx(1.5 + 0.25 * 10).margin(1e-12));
  CHECK(goals[1].positions[0][1] == Approx(-2.0 + 0.25 * 5).margin(1e-12));
  // Undo (the client puts the world before back): goal 2 is cancelled; nothing new is sent.
  robot.world(10, 7);
  robot.wait_state(2, "cancelled");
  REQUIRE(nav2.cancels().size() == 2);
  CHECK(nav2.cancels()[1] == goals[1].id);
  CHECK(goal_count(nav2) == 2);
  CHECK(robot.child->finish() == 0);
}

TEST_CASE("nav2.action must be ROS 2 name tokens", "[dds][nav2]") {
  for (const std::string bad : {"", "a//b", "/abs", "9lives", "bad-name"}) {
    testsupport::ChildProcess c({flipper_bin(), "session", "--set", "nav2.execute=true", "--set",
                                 "nav2.action=" + bad, "--set", "lexicon.path=:memory:"});
    INFO(bad);
    CHECK(c.finish() == 2);
  }
}
