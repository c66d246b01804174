// A planner whose answers break their contract (tests/support/evil_planner) is refused where
// its answers enter the kernel, with the same code and message in every front end: `run`,
// `session`, `serve` (HTTP on 127.0.0.1), `replay` and `bench planners` (`dds`: test_dds_node).
// docs/plugins-untrusted.md. The expected cells are hand-checked on the study map
// (configs/worlds/study2018.json, the robot at [2,4]): "visit room1" goes to room1's [9,0],
// 13 steps for A* around the wall of row 3; the evil planner's straight walk goes east along
// row 4 to [9,4] (steps 1-7) and then south, entering the wall [9,3] on step 8.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "apps/studio/studio_server.hpp"
#include "cli_test_support.hpp"

using namespace flipper;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kEvilDir = std::string(FLIPPER_BINARY_DIR) + "/tests/plugins/evil";
const std::string kEvilFile = kEvilDir + "/evil_planner.so";
const std::string kLabel = "plugin 'evil_planner' (" + kEvilFile + ")";
const std::string kWall = kLabel + ": step 8 enters wall [9,3]";
const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";
const std::string kData = std::string(FLIPPER_SOURCE_DIR) + "/tests/integration/untrusted/data";

// The --set values that select the evil planner in `mode`.
std::vector<std::string> evil_sets(const std::string& mode) {
  return {"plugin_paths=[" + kEvilDir + "]", "planner.plugin=evil_planner",
          "planner.params.mode=" + mode};
}

std::string evil_args(const std::string& mode) {
  std::string args;
  for (const auto& s : evil_sets(mode)) args += " --set " + s;
  return args;
}

// `flipper session` on `lines` with the evil planner in `mode` (and `more` arguments, such as
// another --set): one JSON answer per line.
std::vector<json> session_answers(const std::string& mode, const std::vector<std::string>& lines,
                                  const std::string& name, const std::string& more = "") {
  std::string script;
  for (const auto& l : lines) script += l + "\n";
  const std::string in = clitest::write_file(name + ".jsonl", script);
  const auto r = clitest::run_flipper("session --set lexicon.path=:memory: --set lexicon.preload=" +
                                          evil_args(mode) + more + " " + in,
                                      false);
  INFO(r.out);
  REQUIRE(r.status == 0);
  std::vector<json> answers;
  std::istringstream out(r.out);
  for (std::string line; std::getline(out, line);) answers.push_back(json::parse(line));
  REQUIRE(answers.size() == lines.size());
  return answers;
}

// The shown candidate of a query answer whose formula is `formula`.
json candidate(const json& answer, const std::string& formula) {
  for (const auto& c : answer["candidates"])
    if (c["formula"] == formula) return c;
  FAIL("no candidate '" << formula << "' in " << answer.dump());
  return {};
}

json without_ms(json a) {
  a.erase("ms");
  return a;
}

}  // namespace

TEST_CASE("run: every invalid answer of the evil planner exits 1 with invalid_plan naming it",
          "[untrusted]") {
  struct Case {
    const char* mode;
    const char* utterance;
    std::string message;
  };
  const std::vector<Case> cases{
      {"wall", "visit room1", kWall},
      // The evil `outside` step is [2,-1]: inside the study map's bounds (y from -1), so it is
      // a jump from the robot's [2,4] first.
      {"outside", "visit room1",
       kLabel + ": step 1 jumps from [2,4] to [2,-1], which is not a "
                "neighbour"},
      // The first step of the breadth-first path ([1,4]) left out.
      {"jump", "visit room1",
       kLabel + ": step 1 jumps from [2,4] to [1,3], which is not a "
                "neighbour"},
      // The last step ([9,0]) left out: the path ends on [8,0], beside room1.
      {"goal", "visit room1",
       kLabel + ": the path ends at [8,0], not at the target it reports, "
                "[9,0]"},
      // room1's 9 cells; the order names index 0 twice.
      {"tour", "foreach point in room1 visit point",
       kLabel + ": the tour order [0,1,2,3,4,5,6,7,0] is not a permutation of the 9 points asked"},
  };
  for (const Case& c : cases) {
    INFO("mode " << c.mode << ": " << c.utterance);
    const auto r = clitest::run_flipper("run" + evil_args(c.mode) + " \"" + c.utterance + "\"");
    CHECK(r.out == "flipper run: [invalid_plan] " + c.message + "\n");
    CHECK(r.status == 1);
  }
  // The same requests answered correctly: mode ok walks A*'s 13 steps and exits 0.
  const auto ok = clitest::run_flipper("run" + evil_args("ok") + " \"visit room1\"");
  INFO(ok.out);
  CHECK(ok.status == 0);
  CHECK(clitest::contains(ok.out, "[9,0]"));
  // A plugin that throws is still plugin_error, with the call named (PluginRef).
  const auto thrown = clitest::run_flipper("run" + evil_args("throw") + " \"visit room1\"");
  CHECK(thrown.out ==
        "flipper run: [plugin_error] " + kLabel + ": plan: evil_planner: thrown on purpose\n");
  CHECK(thrown.status == 1);
}

TEST_CASE("session: the candidate carries invalid_plan, nothing of it is applied or acceptable",
          "[untrusted]") {
  const auto a = session_answers("wall",
                                 {R"({"op":"query","text":"visit room1"})",
                                  R"({"op":"accept","rank":0})", R"({"op":"state"})"},
                                 "session-wall");
  const json c = candidate(a[0], "{visit room1}");
  CHECK(c["realizable"] == false);
  CHECK(c["error"] == json{{"code", "invalid_plan"}, {"message", kWall}});
  CHECK(c["trace"] == json::array());
  CHECK(c["world"]["robot"] == json{{"x", 2}, {"y", 4}, {"holding", json::array()}});
  CHECK(a[1]["error"]["code"] == "not_acceptable");
  CHECK(a[1]["error"]["message"] ==
        "candidate 0 cannot be accepted: its execution failed (" + kWall + ")");
  // The robot never moved.
  CHECK(a[2]["world"]["robot"] == json{{"x", 2}, {"y", 4}, {"holding", json::array()}});
}

TEST_CASE("session: a bad answer on a later call refuses the whole candidate", "[untrusted]") {
  // on_call=2: the first plan (13 steps to room1's [9,0]) is valid; the second, to room2's
  // nearest cell [7,0] by [8,0], leaves out its first step. The whole candidate is refused
  // with it (core-language §9: nothing of a failed execution applies).
  const json a = session_answers("jump", {R"({"op":"query","text":"visit room1; visit room2"})"},
                                 "session-on-call", " --set planner.params.on_call=2")[0];
  const json c = candidate(a, "{{visit room1};{visit room2}}");
  CHECK(c["error"] ==
        json{{"code", "invalid_plan"},
             {"message", kLabel + ": step 1 jumps from [9,0] to [7,0], which is not a neighbour"}});
  CHECK(c["trace"] == json::array());
  CHECK(c["realizable"] == false);
  CHECK(c["world"]["robot"] == json{{"x", 2}, {"y", 4}, {"holding", json::array()}});
}

TEST_CASE("session: an accept applies the plan the query showed, without planning again",
          "[untrusted]") {
  // on_call=2: the query's one plan call (13 steps to room1's [9,0]) is answered well, a second
  // call would walk through the wall. The accept applies the previewed execution: no second call
  // (docs/protocol.md, accept). Were it executed again, it would be not_acceptable.
  const auto a = session_answers("wall",
                                 {R"({"op":"query","text":"visit room1"})",
                                  R"({"op":"accept","rank":0})", R"({"op":"state"})"},
                                 "session-accept-no-replan", " --set planner.params.on_call=2");
  const json c = candidate(a[0], "{visit room1}");
  REQUIRE(c["realizable"] == true);
  REQUIRE(c["trace"].size() == 13);
  INFO(a[1].dump());
  CHECK(a[1]["ok"] == true);
  CHECK(a[1]["trace"] == c["trace"]);
  CHECK(a[1]["world"]["robot"] == json{{"x", 9}, {"y", 0}, {"holding", json::array()}});
  CHECK(a[2]["world"]["robot"] == json{{"x", 9}, {"y", 0}, {"holding", json::array()}});
}

TEST_CASE("serve: the same answer as session over HTTP on 127.0.0.1", "[untrusted]") {
  const std::string request = R"({"op":"query","text":"visit room1"})";
  const json expected = session_answers("wall", {request}, "serve-reference")[0];
  studiotest::StudioServer server(studiotest::fresh_dir("untrusted"), evil_sets("wall"));
  auto http = server.client();
  const studiotest::Reply r = studiotest::post(http, "", request);
  CHECK(r.status == 200);
  REQUIRE_FALSE(r.body.is_discarded());
  CHECK(without_ms(r.body) == without_ms(expected));
  CHECK(candidate(r.body, "{visit room1}")["error"] ==
        json{{"code", "invalid_plan"}, {"message", kWall}});
  CHECK(server.stop() == 0);
}

TEST_CASE("replay: the accept is not executed, noted invalid_plan, the message on stderr",
          "[untrusted]") {
  const std::string out = clitest::scratch_dir("untrusted-replay");
  const std::string err = out + "/stderr.txt";
  const auto r =
      clitest::run_shell(kFlipper + " replay --corpus " + kData + "/corpus --no-plots --out " +
                         out + evil_args("wall") + " 2>" + err);
  INFO(r.out << clitest::read_file(err));
  REQUIRE(r.status == 0);
  const std::string stderr_text = clitest::read_file(err);
  CHECK(clitest::contains(stderr_text, "flipper replay: t/A#2: invalid_plan: " + kWall + "\n"));
  // accepts.csv: the one accept, matched at rank 0, not executed, noted invalid_plan.
  std::string accepts;
  for (const auto& entry : fs::recursive_directory_iterator(out + "/latest/"))
    if (entry.path().filename() == "accepts.csv") accepts = clitest::read_file(entry.path());
  INFO(accepts);
  std::istringstream rows(accepts);
  std::string header, row;
  std::getline(rows, header);
  std::getline(rows, row);
  CHECK(row.rfind("t/A#2,t/A,A,a1,1,0,0,", 0) == 0);  // qid,run,group,user,matched,rank,executed
  CHECK(clitest::contains(row, ",invalid_plan,"));
}

TEST_CASE("bench planners: the row's status is invalid_plan, the message on stderr",
          "[untrusted]") {
  const std::string out = clitest::scratch_dir("untrusted-bench");
  const std::string err = out + "/stderr.txt";
  const auto r = clitest::run_shell(kFlipper + " bench planners --experiment " + kData +
                                    "/bench.yaml --no-plots --out " + out +
                                    " --set plugin_paths=[" + kEvilDir + "] 2>" + err);
  INFO(r.out << clitest::read_file(err));
  REQUIRE(r.status == 0);
  CHECK(clitest::read_file(err) ==
        "flipper: bench planners: grid2d x evil, task room1: invalid_plan: " + kWall + "\n");
  const std::string runs = clitest::read_file(out + "/latest/runs.csv");
  INFO(runs);
  std::istringstream rows(runs);
  std::string header, row;
  std::getline(rows, header);
  std::getline(rows, row);
  // world,planner,plugin,seed,task,start,goal,status,success,length,shortest,length_ratio,turns,
  // expansions: no length, turns or expansions of a refused answer; the oracle's 13 steps.
  CHECK(row.rfind(R"(grid2d,evil,evil_planner,,room1,"[2,4]","[9,0]",invalid_plan,0,,13,,0,0,)",
                  0) == 0);
}
