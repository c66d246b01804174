// `flipper session` as another program drives it: spawn the binary, write a line, read its answer
// before writing the next (answers must be flushed), and run a script file.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <fstream>

#include "session_fixture.hpp"

using flipper::kernel::Json;

namespace {

const std::string kFlipper = std::string(FLIPPER_BINARY_DIR) + "/bin/flipper";

class Child {
 public:
  explicit Child(std::vector<std::string> args) {
    int in[2], out[2];
    REQUIRE(pipe(in) == 0);
    REQUIRE(pipe(out) == 0);
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[1]);
      close(out[0]);
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to_ = in[1];
    from_ = out[0];
  }
  ~Child() {
    if (to_ >= 0) close(to_);
    if (from_ >= 0) close(from_);
    if (pid_ > 0 && !waited_) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  void write_line(const std::string& line) {
    std::string l = line + "\n";
    REQUIRE(::write(to_, l.data(), l.size()) == static_cast<ssize_t>(l.size()));
  }
  /// The next output line; empty on end of output or after 30 s.
  std::string read_line() {
    for (;;) {
      if (auto nl = buffer_.find('\n'); nl != std::string::npos) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return line;
      }
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, 30000) <= 0) return {};
      char chunk[4096];
      ssize_t n = ::read(from_, chunk, sizeof chunk);
      if (n <= 0) return {};
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }
  int finish() {
    close(to_);
    to_ = -1;
    int status = 0;
    waitpid(pid_, &status, 0);
    waited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;
  bool waited_ = false;
  std::string buffer_;
};

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
  Child child(command({"-"}));
  child.write_line(R"({"op":"user","name":"ana","id":1})");
  Json a = Json::parse(child.read_line());
  CHECK(a == Json::parse(R"({"ok":true,"op":"user","id":1,"name":"ana"})"));

  child.write_line("");  // ignored: no answer
  child.write_line("garbage");
  CHECK(Json::parse(child.read_line())["error"]["code"] == "bad_json");

  child.write_line(R"({"op":"query","text":"move left"})");
  Json q = Json::parse(child.read_line());
  REQUIRE(q["ok"] == true);
  REQUIRE(!q["candidates"].empty());
  child.write_line(R"({"op":"accept","rank":0})");
  Json acc = Json::parse(child.read_line());
  REQUIRE(acc["ok"] == true);
  child.write_line(R"({"op":"state"})");
  Json st = Json::parse(child.read_line());
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
  Child child(command({script}));
  std::vector<Json> answers;
  for (std::string line = child.read_line(); !line.empty(); line = child.read_line())
    answers.push_back(Json::parse(line));
  CHECK(child.finish() == 0);
  REQUIRE(answers.size() == 3);
  CHECK(answers[0]["id"] == "a");
  CHECK(answers[1]["error"]["code"] == "unknown_op");
  CHECK(answers[2]["id"] == "c");
  CHECK(answers[2]["status"] == "core");
}

TEST_CASE("flipper session with a missing script is a usage error", "[session][cli]") {
  Child child(command({"/nonexistent/script.jsonl"}));
  CHECK(child.read_line().empty());
  CHECK(child.finish() == 2);
}
