// plugins.isolation: process (docs/plugins-untrusted.md §6). A planner that segfaults, aborts,
// runs past its CPU budget or is killed (SIGKILL, from this test) costs the one answer it was
// computing: in `flipper serve` (isolation `auto` is `process` there) user A's candidate carries
// plugin_crashed naming plugin, call and signal, the server stays up, user B's session answers as
// before, and A's next request is answered. The evil planner (tests/support/evil_planner)
// misbehaves only when its correct path ends in column 9 (`on_target_x=9`): "visit room1" from
// the robot's [2,4] on the study map ends at room1's [9,0]; "visit room4" ends at [2,7]
// (hand-checked: room4 spans columns 0-5 of rows 7-8, straight up from the robot).
#include <signal.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "apps/studio/studio_server.hpp"
#include "cli_test_support.hpp"
#include "isolation_test_support.hpp"
#include "process_children.hpp"

using namespace flipper;
using nlohmann::json;
using namespace flipper::isolationtest;
namespace fs = std::filesystem;

namespace {

const std::string kLabel = "plugin 'evil_planner' (" + kEvilDir + "/evil_planner.so)";
const std::string kCrashing = R"({"op":"query","text":"visit room1"})";
const std::string kFine = R"({"op":"query","text":"visit room4"})";

std::vector<std::string> evil_sets(const std::string& mode) {
  return {"plugin_paths=[" + kEvilDir + "]", "planner.plugin=evil_planner",
          "planner.params.mode=" + mode, "planner.params.on_target_x=9"};
}

// The answer to `request` of a fresh `flipper session` with the evil planner in mode ok, in
// process: the reference for user B's answers and A's next one.
json reference(const std::string& request) {
  const std::string in = clitest::write_own_file("isolation-reference.jsonl", request + "\n");
  std::string sets;
  for (const auto& s : evil_sets("ok")) sets += " --set " + s;
  const auto r =
      clitest::run_flipper("session --set lexicon.path=:memory: --set lexicon.preload=" + sets +
                               " --set plugins.isolation=in_process " + in,
                           false);
  REQUIRE(r.status == 0);
  return json::parse(r.out);
}

// The one candidate of a "visit room1" answer.
json only_candidate(const json& answer) {
  REQUIRE(answer["candidates"].size() == 1u);
  return answer["candidates"][0];
}

// The user + system CPU time of process `pid` in clock ticks (/proc/PID/stat fields 14 and 15;
// 10 ms each), 0 when it is gone.
long cpu_ticks(int pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const auto close = stat.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return 0;
  std::istringstream rest(stat.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 13; ++i) rest >> field;  // state .. cmajflt
  long utime = 0, stime = 0;
  rest >> utime >> stime;
  return utime + stime;
}

// Two users of one server: B answered, A's crashing request, B again, A again.
void crash_costs_one_answer(studiotest::StudioServer& server, const json& expected_error,
                            const std::function<void()>& meanwhile = {}) {
  const json fine = without_ms(reference(kFine));
  auto http_a = server.client();
  auto http_b = server.client();
  const auto a = studiotest::post(http_a, "", R"({"op":"state"})");
  const auto b = studiotest::post(http_b, "", R"({"op":"state"})");
  REQUIRE(a.status == 200);
  REQUIRE(b.status == 200);
  REQUIRE(a.session != b.session);
  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine);

  auto crashing = std::async(std::launch::async,
                             [&] { return studiotest::post(http_a, a.session, kCrashing); });
  if (meanwhile) meanwhile();
  const auto crashed = crashing.get();
  CHECK(crashed.status == 200);
  const json c = only_candidate(crashed.body);
  CHECK(c["formula"] == "{visit room1}");
  CHECK(c["error"] == expected_error);
  CHECK(c["realizable"] == false);
  CHECK(c["trace"] == json::array());
  CHECK(c["world"]["robot"] == json{{"x", 2}, {"y", 4}, {"holding", json::array()}});
  // Accepting it is refused with the message quoted; nothing was applied.
  const auto accept = studiotest::post(http_a, a.session, R"({"op":"accept","rank":0})");
  CHECK(accept.body["ok"] == false);
  CHECK(accept.body["error"]["code"] == "not_acceptable");

  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine);
  CHECK(without_ms(studiotest::post(http_a, a.session, kFine).body) == fine);
  CHECK(server.stop() == 0);
}

json crash_error(const std::string& what) {
  return json{{"code", "plugin_crashed"}, {"message", kLabel + ": plan: " + what}};
}

}  // namespace

TEST_CASE("serve: a planner that segfaults costs user A one answer, user B nothing",
          "[isolation]") {
  studiotest::StudioServer server(studiotest::fresh_dir("isolation"),
                                  isolated_server(evil_sets("segv")));
  crash_costs_one_answer(server, crash_error("SIGSEGV"));
}

TEST_CASE("serve: a planner that aborts costs user A one answer, user B nothing", "[isolation]") {
  studiotest::StudioServer server(studiotest::fresh_dir("isolation"),
                                  isolated_server(evil_sets("abort")));
  crash_costs_one_answer(server, crash_error("SIGABRT"));
}

TEST_CASE("serve: a planner that spins past its CPU budget is ended by it (SIGXCPU)",
          "[isolation]") {
  // execution.cpu_budget_ms = 100: the child is ended after at most 100 ms + 1 s of CPU time.
  auto sets = evil_sets("hang");
  sets.push_back("execution.cpu_budget_ms=100");
  studiotest::StudioServer server(studiotest::fresh_dir("isolation"), isolated_server(sets));
  crash_costs_one_answer(
      server,
      crash_error("SIGXCPU (still running 1000 ms of CPU time after its budget was spent)"));
}

TEST_CASE("serve: the plan's process killed from outside (SIGKILL) costs one answer",
          "[isolation]") {
  // The planner spins (its CPU limit, 2 s + 1 s, is far); this test finds the server's child
  // that has spent 50 ms of CPU time, the plan call's process (the query's parse has a child of
  // its own first, done in a few ms), and kills it.
  studiotest::StudioServer server(studiotest::fresh_dir("isolation"),
                                  isolated_server(evil_sets("hang")));
  const int pid = server.pid();
  crash_costs_one_answer(server, crash_error("SIGKILL"), [pid] {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int spinning = 0;
    while (spinning == 0 && std::chrono::steady_clock::now() < until) {
      for (const int kid : testsupport::children_of(pid))
        if (cpu_ticks(kid) >= 5) spinning = kid;
      if (spinning == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    REQUIRE(spinning != 0);
    REQUIRE(::kill(spinning, SIGKILL) == 0);
  });
}

TEST_CASE("run: process isolation answers plugin_crashed and exits 1, in_process dies as before",
          "[isolation]") {
  std::string sets;
  for (const auto& s : evil_sets("segv")) sets += " --set " + s;
  const auto isolated = clitest::run_flipper("run" + sets +
                                             " --set plugins.isolation=process "
                                             "\"visit room1\"");
  CHECK(isolated.status == 1);
  CHECK(isolated.out == "flipper run: [plugin_crashed] " + kLabel + ": plan: SIGSEGV\n");
  // `auto` is in_process outside the servers: the crash ends the process, as it always did (in
  // the instrumented build too: ASan would catch the SIGSEGV and exit 1 unless told not to).
  const auto in_process =
      clitest::run_shell("ASAN_OPTIONS=handle_segv=0 " + std::string(FLIPPER_BINARY_DIR) +
                         "/bin/flipper run" + sets + " \"visit room1\" 2>&1");
  CHECK(in_process.status == 128 + SIGSEGV);
  const auto fine = clitest::run_flipper("run" + sets +
                                         " --set plugins.isolation=process "
                                         "\"visit room4\"");
  CHECK(fine.status == 0);
}
