// Task goals as predicates (docs/studio.md §7 "Goals"): each condition against hand-built worlds at
// its boundaries, the study file's refusals word for word, and a participant who reaches a room by
// another cell than any goal world would name, with the time the task took on the goal line.
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/sdk/errors.hpp"
#include "studio_server.hpp"
#include "study.hpp"
#include "task_goal.hpp"

namespace flipper::studiotest {
namespace {

namespace fs = std::filesystem;
using studio::TaskGoal;

// configs/worlds/study2018.json: the robot at (2,4) in room3; red items at (10,8) room5, (7,4)
// room3 and (4,0) room2; room1 is x 9..11, y 0..2; (0,7) is in room4.
std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

json start_world() {
  return json::parse(read_text(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json"));
}

TaskGoal goal(const std::string& yaml) {
  return TaskGoal::of_predicate(YAML::Load(yaml), start_world(), "s.yaml", "tasks[0].goal");
}

json with_robot(json w, int x, int y) {
  w["robot"]["x"] = x;
  w["robot"]["y"] = y;
  return w;
}

// Moves every lying item of `color` to (x, y).
json move_items(json w, const std::string& color, int x, int y) {
  for (auto& i : w["items"])
    if (i["color"] == color) {
      i["x"] = x;
      i["y"] = y;
    }
  return w;
}

// Picks up the first lying item of `color` (it leaves the items, the robot holds it).
json pick(json w, const std::string& color) {
  auto& items = w["items"];
  for (auto it = items.begin(); it != items.end(); ++it)
    if ((*it)["color"] == color) {
      w["robot"]["holding"].push_back({{"color", (*it)["color"]}, {"shape", (*it)["shape"]}});
      items.erase(it);
      break;
    }
  return w;
}

std::string refusal(const std::string& goal_yaml) {
  const std::string dir = fresh_dir("study-goal-refused");
  std::ofstream(dir + "/start.json") << start_world().dump();
  std::ofstream(dir + "/s.yaml") << "name: g\ntasks:\n  - {name: one, text: t, start: start.json, "
                                    "goal: " +
                                        goal_yaml + "}\n";
  try {
    studio::Study::load(dir + "/s.yaml");
  } catch (const sdk::Error& e) {
    const std::string what = e.what();
    const std::string prefix = "study " + dir + "/s.yaml: ";
    REQUIRE(what.rfind(prefix, 0) == 0);
    CHECK(e.code() == "bad_config");
    return what.substr(prefix.size());
  }
  return "(accepted)";
}

}  // namespace

TEST_CASE("goal predicates: the robot in a room or at a cell, at the room's edge", "[goals]") {
  const json w = start_world();
  CHECK(goal("{robot_in: room3}").reached(w));
  CHECK_FALSE(goal("{robot_in: room1}").reached(w));
  CHECK(goal("{robot_in: room1}").reached(with_robot(w, 9, 0)));        // room1's first column
  CHECK_FALSE(goal("{robot_in: room1}").reached(with_robot(w, 8, 0)));  // one cell left of it
  CHECK(goal("{robot_in: room1}").reached(with_robot(w, 11, 2)));
  CHECK_FALSE(goal("{robot_in: room1}").reached(with_robot(w, 11, 3)));  // one row above
  CHECK(goal("{robot_at: [2, 4]}").reached(w));
  CHECK_FALSE(goal("{robot_at: [2, 5]}").reached(w));
  CHECK_FALSE(goal("{robot_at: [2, 4], robot_in: room1}").reached(w));  // every condition holds
}

TEST_CASE("goal predicates: all items of a colour, or an exact count, lying or held", "[goals]") {
  const json w = start_world();
  const TaskGoal all_red = goal("{items: [{color: red, in: room4}]}");
  CHECK_FALSE(all_red.reached(w));                     // none of the three is there
  CHECK(all_red.reached(move_items(w, "red", 0, 7)));  // all three are
  CHECK_FALSE(all_red.reached(pick(move_items(w, "red", 0, 7), "red")));  // one is held
  CHECK_FALSE(goal("{items: [{color: purple, in: room4}]}").reached(w));  // all of none: no
  // Exactly N: red in room3 is the circle at (7,4) alone.
  CHECK(goal("{items: [{color: red, in: room3, count: 1}]}").reached(w));
  CHECK_FALSE(goal("{items: [{color: red, in: room3, count: 2}]}").reached(w));
  CHECK_FALSE(goal("{items: [{color: red, in: room3, count: 0}]}").reached(w));
  CHECK(goal("{items: [{color: purple, in: room4, count: 0}]}").reached(w));
  CHECK(goal("{items: [{color: red, shape: circle, in: room3}]}").reached(w));
  CHECK_FALSE(goal("{items: [{color: red, shape: triangle, in: room3}]}").reached(w));
  // Held: one red item picked up.
  const json holding = pick(w, "red");
  CHECK(goal("{items: [{color: red, held: true, count: 1}]}").reached(holding));
  CHECK_FALSE(goal("{items: [{color: red, held: true, count: 2}]}").reached(holding));
  CHECK_FALSE(goal("{items: [{color: red, held: true}]}").reached(holding));  // not all held
  CHECK_FALSE(goal("{items: [{color: red, held: true, count: 1}]}").reached(w));
  // Normalised for the page.
  CHECK(goal("{robot_in: room1, items: [{color: red, in: room4}]}").predicate() ==
        json{{"robot_in", "room1"},
             {"items", json::array({{{"color", "red"}, {"in", "room4"}, {"count", "all"}}})}});
}

TEST_CASE("goal predicates: the study file's mistakes are named", "[goals]") {
  CHECK(refusal("{robot_inn: room1}") ==
        "tasks[0].goal: unknown key 'robot_inn' (known: items, robot_at, robot_in)");
  CHECK(refusal("{robot_in: kitchen}") ==
        "tasks[0].goal.robot_in: the task's start world has no room 'kitchen'");
  CHECK(refusal("{robot_at: [1]}") == "tasks[0].goal.robot_at: must be a cell [x, y] or [x, y, z]");
  CHECK(refusal("{items: [{color: red}]}") ==
        "tasks[0].goal.items[0]: give exactly one of 'in: ROOM' and 'held: true'");
  CHECK(refusal("{items: [{color: red, in: room4, held: true}]}") ==
        "tasks[0].goal.items[0]: give exactly one of 'in: ROOM' and 'held: true'");
  CHECK(refusal("{items: [{color: red, in: room9}]}") ==
        "tasks[0].goal.items[0].in: the task's start world has no room 'room9'");
  CHECK(refusal("{items: [{color: red, in: room4, count: -1}]}") ==
        "tasks[0].goal.items[0].count: must not be negative");
  CHECK(refusal("{items: [{color: red, in: room4, count: many}]}") ==
        "tasks[0].goal.items[0].count: must be 'all' or a number of items, not 'many'");
  CHECK(refusal("{items: [{colour: red, in: room4}]}") ==
        "tasks[0].goal.items[0]: unknown key 'colour' (known: color, count, held, in, shape)");
  CHECK(refusal("{}") ==
        "tasks[0].goal: a goal is a world file or a map of robot_in, robot_at "
        "and items");
}

TEST_CASE("a participant reaches a predicate goal, the goal line has the time of the task",
          "[goals]") {
  const std::string dir = fresh_dir("study-goal-predicate");
  std::ofstream(dir + "/start.json") << start_world().dump();
  std::ofstream(dir + "/study.yaml")
      << "name: g\ngroups: [B]\nrecord: rec\ntasks:\n"
         "  - {name: one, text: go, start: start.json, goal: {robot_in: room1}}\n";
  StudioServer server(dir, {"serve.study=" + dir + "/study.yaml"});
  auto http = server.client();
  httplib::Headers headers;
  std::string session;
  auto send = [&](const json& request) {
    Reply r = post(http, session, request.dump(), headers, "");
    if (!r.session.empty()) session = r.session;
    if (!r.set_cookie.empty()) headers = cookie(r.set_cookie.substr(0, r.set_cookie.find(';')));
    return r;
  };
  const auto started = std::chrono::steady_clock::now();
  REQUIRE(send({{"op", "world"},
                {"world", start_world()},
                {"studio", {{"why", "task_start"}, {"task", 0}}}})
              .body["ok"] == true);
  REQUIRE(send({{"op", "query"}, {"text", "move right"}}).body["ok"] == true);
  Reply r = send({{"op", "accept"}, {"rank", 0}});
  CHECK(r.goal.empty());  // (3,4): room3 still
  REQUIRE(send({{"op", "query"}, {"text", "visit room1"}}).body["ok"] == true);
  r = send({{"op", "accept"}, {"rank", 0}});
  CHECK(r.goal == "reached");
  const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::steady_clock::now() - started)
                           .count();
  // "visit room1" ends at (9,0), the room's nearest cell: a goal world with the robot at (9,1),
  // as examples/study/goal-room1.json had, would not count it.
  CHECK(r.body["world"]["robot"] == json{{"holding", json::array()}, {"x", 9}, {"y", 0}});
  std::vector<json> goals;
  std::istringstream lines(read_text(fs::path(dir) / "rec" / "queries.jsonl"));
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && json::parse(line)["kind"] == "goal") goals.push_back(json::parse(line));
  REQUIRE(goals.size() == 1);
  REQUIRE(goals[0]["task_ms"].is_number_integer());
  // Within the test's own clock around the task (task_start to the accept that reached it).
  CHECK(goals[0]["task_ms"].get<std::int64_t>() <= elapsed);
}

}  // namespace flipper::studiotest
