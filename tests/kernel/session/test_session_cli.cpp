// `flipper session` as another program drives it: spawn the binary, write a line, read its answer
// before writing the next (answers must be flushed), and run a script file.
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;

namespace {

const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";

/// The next answer line; empty at the end of output or after 30 s.
std::string next_line(flipper::testsupport::ChildProcess& child) {
  return child.read_line(std::chrono::seconds(30));
}

std::vector<std::string> command(std::vector<std::string> tail) {
  std::vector<std::string> args{kFlipper, "session"};
  for (const auto& o : flipper::testsupport::test_overrides()) {
    args.push_back("--set");
    args.push_back(o);
  }
  args.insert(args.end(), tail.begin(), tail.end());
  return args;
}

}  // namespace

TEST_CASE("flipper session answers each line as it arrives", "[session][cli]") {
  flipper::testsupport::ChildProcess child(command({"-"}));
  REQUIRE(child.write_line(R"({"op":"user","name":"ana","id":1})"));
  Json a = Json::parse(next_line(child));
  CHECK(a == Json::parse(R"({"ok":true,"op":"user","id":1,"name":"ana"})"));

  REQUIRE(child.write_line(""));  // ignored: no answer
  REQUIRE(child.write_line("garbage"));
  CHECK(Json::parse(next_line(child))["error"]["code"] == "bad_json");

  REQUIRE(child.write_line(R"({"op":"query","text":"move left"})"));
  Json q = Json::parse(next_line(child));
  REQUIRE(q["ok"] == true);
  REQUIRE(!q["candidates"].empty());
  REQUIRE(child.write_line(R"({"op":"accept","rank":0})"));
  Json acc = Json::parse(next_line(child));
  REQUIRE(acc["ok"] == true);
  REQUIRE(child.write_line(R"({"op":"state"})"));
  Json st = Json::parse(next_line(child));
  CHECK(st["world"] == acc["world"]);
  CHECK(st["world"]["robot"]["x"] == 1);
  CHECK(child.finish() == 0);
}

TEST_CASE("flipper session runs a script file, one answer per request", "[session][cli]") {
  std::string script = flipper::testsupport::scratch_path("script") + ".jsonl";
  std::ofstream(script) << R"({"op":"state","id":"a"})"
                        << "\n\n"
                        << R"({"op":"nope","id":"b"})"
                        << "\n"
                        << R"({"op":"query","text":"move up","id":"c"})"
                        << "\n";
  flipper::testsupport::ChildProcess child(command({script}));
  std::vector<Json> answers;
  for (std::string line = next_line(child); !line.empty(); line = next_line(child))
    answers.push_back(Json::parse(line));
  CHECK(child.finish() == 0);
  REQUIRE(answers.size() == 3);
  CHECK(answers[0]["id"] == "a");
  CHECK(answers[1]["error"]["code"] == "unknown_op");
  CHECK(answers[2]["id"] == "c");
  CHECK(answers[2]["status"] == "core");
}

TEST_CASE("flipper session with a missing script is a usage error", "[session][cli]") {
  flipper::testsupport::ChildProcess child(command({"/nonexistent/script.jsonl"}));
  CHECK(next_line(child).empty());
  CHECK(child.finish() == 2);
}
