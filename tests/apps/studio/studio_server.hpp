#pragma once
// A real `flipper serve` on a free loopback port (serve.port=0, the port read from its first
// line) with its lexicon in a fresh directory, and an httplib client for it.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace flipper::studiotest {

using nlohmann::json;

inline std::string fresh_dir(const std::string& name) {
  std::random_device rd;
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "studio" /
                   (name + "-" + std::to_string(rd()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// A command's exit status and output.
struct CliRun {
  int status = 0;
  std::string out;
};
/// A shell command's exit status and output (stdout and stderr).
inline CliRun run_shell(const std::string& cmd) {
  CliRun r;
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p) != nullptr) r.out += buf;
  const int raw = ::pclose(p);
  REQUIRE(WIFEXITED(raw));
  r.status = WEXITSTATUS(raw);
  return r;
}
/// `flipper ARGS` with `input` on standard input (a file in `dir`): status and output.
inline CliRun run_flipper(const std::string& args, const std::string& dir,
                          const std::string& input = "") {
  const std::string in = dir + "/stdin.txt";
  {
    std::ofstream f(in, std::ios::trunc);
    f << input;
  }
  return run_shell(std::string(FLIPPER_BINARY_DIR) + "/bin/flipper " + args + " < " + in + " 2>&1");
}

class StudioServer {
 public:
  /// Starts the server with `sets` (--set values) after the test defaults.
  explicit StudioServer(std::string dir, const std::vector<std::string>& sets = {})
      : dir_(std::move(dir)) {
    std::vector<std::string> args{std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", "serve"};
    for (const std::string& s : {std::string("serve.host=127.0.0.1"), std::string("serve.port=0"),
                                 "lexicon.path=" + lexicon(), std::string("lexicon.preload=")}) {
      args.push_back("--set");
      args.push_back(s);
    }
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
      // The keys that choose the accounts store: `flipper accounts` must open the same one.
      if (s.rfind("serve.study=", 0) == 0 || s.rfind("serve.accounts=", 0) == 0)
        account_sets_ += " --set '" + s + "'";
    }
    child_ = std::make_unique<testsupport::ChildProcess>(args);
    const std::string line = child_->read_line(std::chrono::seconds(30));
    const auto at = line.find("127.0.0.1:");
    REQUIRE(at != std::string::npos);  // "flipper serve: listening on http://127.0.0.1:PORT/"
    port_ = std::stoi(line.substr(at + 10));
  }

  int port() const { return port_; }
  const std::string& dir() const { return dir_; }
  /// `flipper accounts add NAME` on this server's store (the server reads it on every login).
  void add_account(const std::string& name, const std::string& password,
                   const std::string& role = "user") const {
    REQUIRE(run_accounts("add " + name + " --role " + role, password + "\n").status == 0);
  }
  /// `flipper accounts ARGS` with `input` on standard input: status and output.
  CliRun run_accounts(const std::string& args, const std::string& input = "") const {
    return run_flipper("accounts " + args + " --set lexicon.path=" + lexicon() + account_sets_,
                       dir_, input);
  }
  std::string lexicon() const { return dir_ + "/lexicon.sqlite"; }
  std::string origin() const { return "http://127.0.0.1:" + std::to_string(port_); }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(10);
    c.set_read_timeout(30);
    c.set_tcp_nodelay(true);
    return c;
  }
  void kill() { child_->kill_now(); }
  int pid() const { return child_->pid(); }
  /// What the server wrote to standard output after its first line, up to its exit (after stop()).
  std::string rest_of_output() { return child_->read_all(); }
  /// SIGTERM and wait: the exit status.
  int stop() {
    ::kill(child_->pid(), SIGTERM);
    return child_->finish();
  }

 private:
  std::string dir_;
  std::unique_ptr<testsupport::ChildProcess> child_;
  int port_ = 0;
  std::string account_sets_;  ///< --set of serve.study / serve.accounts: the server's store
};

/// POST one request; the reply's status, body and session token.
struct Reply {
  int status = 0;
  json body;
  std::string text;
  std::string session;
  std::string user;
  std::string set_cookie;  ///< a new login's Set-Cookie (study enrollment)
  std::string goal;        ///< Flipper-Goal (study mode)
};

/// `group`: a new session's ?group= (study mode).
inline Reply post(httplib::Client& c, const std::string& session, const std::string& body,
                  const httplib::Headers& headers = {}, const std::string& group = "") {
  const std::string path = !session.empty() ? "/api/v1/request?session=" + session
                           : group.empty()  ? std::string("/api/v1/request")
                                            : "/api/v1/request?group=" + group;
  auto res = c.Post(path.c_str(), headers, body, "application/json");
  REQUIRE(res);
  Reply r;
  r.status = res->status;
  r.text = res->body;
  r.body = json::parse(res->body, nullptr, false);
  r.session = res->get_header_value("Flipper-Session");
  r.user = res->get_header_value("Flipper-User");
  r.set_cookie = res->get_header_value("Set-Cookie");
  r.goal = res->get_header_value("Flipper-Goal");
  return r;
}

inline Reply post_json(httplib::Client& c, const std::string& session, const json& request) {
  return post(c, session, request.dump());
}

/// POST /api/v1/login; the Cookie header value of the login ("" when refused).
inline std::string login(httplib::Client& c, const json& credentials, int* status = nullptr) {
  auto res = c.Post("/api/v1/login", credentials.dump(), "application/json");
  REQUIRE(res);
  if (status != nullptr) *status = res->status;
  const std::string set = res->get_header_value("Set-Cookie");
  return set.substr(0, set.find(';'));
}

inline httplib::Headers cookie(const std::string& value) {
  return {{"Cookie", value}};
}

/// A session of its own: its token (from a first `state` request).
inline std::string new_session(httplib::Client& c, const httplib::Headers& headers = {}) {
  const Reply r = post(c, "", json{{"op", "state"}}.dump(), headers);
  REQUIRE(r.status == 200);
  REQUIRE(r.session.size() == 32);
  return r.session;
}

}  // namespace flipper::studiotest
