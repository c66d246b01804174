// What the studio stores, on a disk that fails and on a fresh HOME (docs/studio.md §7 "Nothing
// lost silently", docs/accounts.md §4): a study whose recording cannot be written answers 503
// write_failed, keeps every file byte for byte and records again once it can; the first
// `flipper accounts add` or `flipper serve` on an empty HOME creates the data folder, private.
#include <sys/resource.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The recording's files, byte for byte; the study's accounts store beside them (SQLite: its
// shared-memory index changes on every read) is not part of the recording.
std::map<std::string, std::string> folder_contents(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("accounts.sqlite", 0) != 0)
      out[e.path().filename().string()] = read_file(e.path());
  return out;
}

unsigned mode_of(const fs::path& path) {
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  return st.st_mode & 07777;
}

void limit_file_size(int pid, rlim_t bytes) {
  rlimit limit{};
  REQUIRE(::prlimit(pid, RLIMIT_FSIZE, nullptr, &limit) == 0);
  limit.rlim_cur = bytes;
  REQUIRE(::prlimit(pid, RLIMIT_FSIZE, &limit, nullptr) == 0);
}

TEST_CASE("a study whose recording cannot be written refuses write_failed and keeps its files") {
  const std::string dir = fresh_dir("study-full");
  std::ofstream(dir + "/study.yaml") << "name: t\ngroups: [B]\nrecord: rec\ntasks:\n"
                                        "  - {name: one, text: anything, start: start.json}\n";
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json",
                dir + "/start.json");
  StudioServer server(dir, {"serve.study=" + dir + "/study.yaml"});
  auto http = server.client();
  Reply r = post(http, "", json{{"op", "query"}, {"text", "move left"}}.dump());
  REQUIRE(r.status == 200);
  const std::string login = r.set_cookie.substr(0, r.set_cookie.find(';'));
  const std::string session = r.session;
  const fs::path rec = fs::path(dir) / "rec";
  const auto before = folder_contents(rec);
  REQUIRE(before.count("queries.jsonl") == 1);
  REQUIRE(before.count("participants.json") == 1);

  // Every file is at least 1 byte: a 1-byte limit refuses each append and each new file.
  limit_file_size(server.pid(), 1);
  for (const char* text : {"move right", "move up"}) {
    r = post(http, session, json{{"op", "query"}, {"text", text}}.dump(), cookie(login));
    CHECK(r.status == 503);
    CHECK(r.body["error"]["code"] == "write_failed");
    const std::string message = r.body["error"]["message"];
    CHECK_THAT(message, Catch::Contains("could not store") && Catch::Contains("File too large"));
    CHECK(message.find(dir) == std::string::npos);  // no server path in a client's message
  }
  CHECK(folder_contents(rec) == before);  // byte for byte, no temporary left

  // The disk has room again: the next request is answered and recorded.
  limit_file_size(server.pid(), RLIM_INFINITY);
  r = post(http, session, json{{"op", "query"}, {"text", "move down"}}.dump(), cookie(login));
  CHECK(r.status == 200);
  CHECK(r.body["ok"] == true);
  const std::string queries = read_file(rec / "queries.jsonl");
  CHECK(queries.size() > before.at("queries.jsonl").size());
  CHECK(queries.find("move down") != std::string::npos);
  CHECK(queries.back() == '\n');
  CHECK(server.stop() == 0);
}

TEST_CASE("a group that cannot learn is refused define with teaching_off") {
  const std::string dir = fresh_dir("study-group-a");
  std::ofstream(dir + "/study.yaml") << "name: t\ngroups: [A]\nrecord: rec\ntasks:\n"
                                        "  - {name: one, text: anything, start: start.json}\n";
  fs::copy_file(fs::path(FLIPPER_SOURCE_DIR) / "configs/worlds/study2018.json",
                dir + "/start.json");
  StudioServer server(dir, {"serve.study=" + dir + "/study.yaml"});
  auto http = server.client();
  Reply r = post(http, "", json{{"op", "query"}, {"text", "move left"}}.dump());
  REQUIRE(r.status == 200);
  const auto login = cookie(r.set_cookie.substr(0, r.set_cookie.find(';')));
  r = post(http, r.session, json{{"op", "define"}, {"head", "hop"}, {"body", {"move up"}}}.dump(),
           login);
  CHECK(r.status == 200);
  CHECK(r.body["ok"] == false);
  CHECK(r.body["error"]["code"] == "teaching_off");
  CHECK(
      post(http, r.session, json{{"op", "query"}, {"text", "hop"}}.dump(), login).body["status"] ==
      "unparsable");
}

// `flipper ARGS` with HOME=`home` and `input` on stdin: status and output.
CliRun run_with_home(const std::string& home, const std::string& args, const std::string& input) {
  const std::string in = home + "-stdin.txt";
  std::ofstream(in) << input;
  return run_shell("env HOME=" + home + " " + std::string(FLIPPER_BINARY_DIR) + "/bin/flipper " +
                   args + " < " + in + " 2>&1");
}

TEST_CASE("the first `accounts add` on an empty HOME creates the data folder, private") {
  const std::string home = fresh_dir("first-run-accounts") + "/home";
  fs::create_directories(home);
  const CliRun r = run_with_home(home, "accounts add ana", "a long password\n");
  CHECK(r.status == 0);
  INFO(r.out);
  const fs::path data = fs::path(home) / ".local/share/flipper";
  CHECK(fs::is_regular_file(data / "accounts.sqlite"));
  CHECK(mode_of(data) == 0700);
  CHECK(mode_of(fs::path(home) / ".local/share") == 0700);
  CHECK(mode_of(fs::path(home) / ".local") == 0700);
  CHECK(mode_of(data / "accounts.sqlite") == 0600);
  CHECK(run_with_home(home, "accounts list", "").out.find("ana") != std::string::npos);
}

TEST_CASE("the first `flipper serve` on an empty HOME creates the data folder and serves") {
  const std::string home = fresh_dir("first-run-serve") + "/home";
  fs::create_directories(home);
  testsupport::ChildProcess child({"/usr/bin/env", "HOME=" + home,
                                   std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", "serve",
                                   "--set", "serve.port=0", "--set", "lexicon.preload="});
  const std::string line = child.read_line(std::chrono::seconds(60));
  INFO(line);
  const auto at = line.find("127.0.0.1:");
  REQUIRE(at != std::string::npos);
  httplib::Client c("127.0.0.1", std::stoi(line.substr(at + 10)));
  c.set_read_timeout(30);
  const Reply r = post(c, "", json{{"op", "query"}, {"text", "move left"}}.dump());
  CHECK(r.status == 200);
  const fs::path data = fs::path(home) / ".local/share/flipper";
  CHECK(mode_of(data) == 0700);
  CHECK(mode_of(data / "accounts.sqlite") == 0600);
  CHECK(fs::is_regular_file(data / "lexicon.sqlite"));
  ::kill(child.pid(), SIGTERM);
  CHECK(child.finish() == 0);
}

TEST_CASE("accounts passwd and role end the account's logins and so its sessions") {
  StudioServer server(fresh_dir("passwd"));
  server.add_account("ana", "a long password");
  auto http = server.client();
  for (const std::string action : {"passwd ana", "role ana --role admin"}) {
    INFO(action);
    const std::string login =
        studiotest::login(http, {{"name", "ana"}, {"password", "a long password"}});
    REQUIRE_FALSE(login.empty());
    const std::string second =
        studiotest::login(http, {{"name", "ana"}, {"password", "a long password"}});
    const std::string session = new_session(http, cookie(login));
    CHECK(post(http, session, R"({"op":"state"})", cookie(login)).status == 200);
    const CliRun r = server.run_accounts(action, "a long password\n");
    CHECK(r.status == 0);
    CHECK_THAT(r.out, Catch::Contains("; 2 logins ended"));
    const Reply after = post(http, session, R"({"op":"state"})", cookie(login));
    CHECK(after.status == 401);
    CHECK(after.body["error"]["code"] == "login_required");
    auto info = http.Get("/api/v1/info", cookie(second));
    REQUIRE(info);
    CHECK(json::parse(info->body)["account"].is_null());  // the other browser's login too
  }
  const CliRun listed = server.run_accounts("list --json");
  CHECK_THAT(listed.out, Catch::Contains("\"role\":\"admin\""));
}

// Root passes file modes: the server runs without its DAC-override capabilities, so the modes
// bind it (as they bind any other user).
std::vector<std::string> without_dac_override() {
  if (::geteuid() != 0) return {};
  return {"/usr/bin/setpriv", "--bounding-set=-dac_override,-dac_read_search,-fowner", "--"};
}

TEST_CASE("on a read-only store the server starts, serves reads and logins, refuses writes") {
  const std::string dir = fresh_dir("read-only-store");
  std::string cookie_value;
  {
    StudioServer server(dir);
    server.add_account("ana", "a long password");
    auto http = server.client();
    cookie_value = studiotest::login(http, {{"name", "ana"}, {"password", "a long password"}});
    REQUIRE_FALSE(cookie_value.empty());
    const std::string s = new_session(http);
    REQUIRE(
        post_json(http, s, {{"op", "define"}, {"head", "hop"}, {"body", {"move up"}}}).body["ok"] ==
        true);
    CHECK(server.stop() == 0);
  }
  for (const auto& e : fs::directory_iterator(dir))
    fs::permissions(e.path(), fs::perms::owner_read);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  struct Restore {
    std::string dir;
    ~Restore() {
      fs::permissions(dir, fs::perms::owner_all);
      for (const auto& e : fs::directory_iterator(dir))
        fs::permissions(e.path(), fs::perms::owner_read | fs::perms::owner_write);
    }
  } restore{dir};

  std::vector<std::string> args = without_dac_override();
  for (const std::string& a :
       {std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", std::string("serve"),
        std::string("--set"), std::string("serve.port=0"), std::string("--set"),
        "lexicon.path=" + dir + "/lexicon.sqlite", std::string("--set"),
        std::string("lexicon.preload=")})
    args.push_back(a);
  testsupport::ChildProcess child(args);
  const std::string line = child.read_line(std::chrono::seconds(60));
  INFO(line);
  const auto at = line.find("127.0.0.1:");
  REQUIRE(at != std::string::npos);  // it started
  httplib::Client http("127.0.0.1", std::stoi(line.substr(at + 10)));
  http.set_read_timeout(30);
  // An existing login opens a session; the stored rule is read.
  const std::string s = new_session(http, cookie(cookie_value));
  Reply r = post(http, s, R"({"op":"query","text":"hop"})", cookie(cookie_value));
  CHECK(r.user == "ana");
  CHECK(r.body["status"] == "induced");
  // Writes: a definition, a new login.
  r = post(http, s, json{{"op", "define"}, {"head", "jump"}, {"body", {"move up"}}}.dump(),
           cookie(cookie_value));
  CHECK(r.body["ok"] == false);
  CHECK(r.body["error"]["code"] == "lexicon_read_only");
  int status = 0;
  CHECK(
      studiotest::login(http, {{"name", "ana"}, {"password", "a long password"}}, &status).empty());
  CHECK(status == 503);
  auto res =
      http.Post("/api/v1/login", json{{"name", "ana"}, {"password", "a long password"}}.dump(),
                "application/json");
  REQUIRE(res);
  CHECK(json::parse(res->body)["error"]["code"] == "read_only");
  // A guest gets a name no counter gives.
  r = post(http, "", R"({"op":"state"})");
  CHECK(r.status == 200);
  CHECK_THAT(r.user, Catch::StartsWith("guest-r"));
  ::kill(child.pid(), SIGTERM);
  CHECK(child.finish() == 0);
}

}  // namespace
}  // namespace flipper::studiotest
