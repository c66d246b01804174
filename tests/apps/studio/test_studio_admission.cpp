// Admission under many addresses (docs/studio.md §2 "Descriptors", §4 "Admission"): the
// descriptor limit is raised to its hard limit and the connection cap kept below it, so a flood
// of connections from many loopback addresses meets 503s, not EMFILE; and when descriptors do
// run out, the server refuses and backs off instead of spinning.
#include <sys/resource.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "raw_socket.hpp"
#include "registry.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

// User + system CPU seconds of process `pid` (/proc/PID/stat).
double cpu_seconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string skip;
  for (int i = 3; i < 14; ++i) fields >> skip;  // fields 3..13
  long utime = 0, stime = 0;
  fields >> utime >> stime;
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

struct Flood {
  std::vector<std::unique_ptr<RawSocket>> sockets;
  int refused = 0;  ///< answered 503 too_many_connections and closed
};

// `per_address` connections from each of 127.0.0.(first..first+addresses-1), held open.
Flood flood(int port, int first, int addresses, int per_address) {
  Flood f;
  for (int a = 0; a < addresses; ++a)
    for (int i = 0; i < per_address; ++i) {
      auto s = std::make_unique<RawSocket>(port, "127.0.0." + std::to_string(first + a));
      if (s->connected()) f.sockets.push_back(std::move(s));
    }
  // A refusal is written at accept: the first look finds nearly all, a second one the last few.
  std::vector<bool> seen(f.sockets.size(), false);
  for (const int wait_ms : {5, 1}) {
    for (std::size_t i = 0; i < f.sockets.size(); ++i) {
      if (seen[i]) continue;
      bool closed = false;
      const std::string text = f.sockets[i]->read_all(std::chrono::milliseconds(wait_ms), &closed);
      if (closed && text.find("too_many_connections") != std::string::npos) {
        ++f.refused;
        seen[i] = true;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  return f;
}

TEST_CASE("under a descriptor limit of 256 the connection cap fits it: a flood meets 503s") {
  const std::string dir = fresh_dir("nofile-cap");
  // The hard limit is 256: the server cannot raise it, so it caps its connections below.
  testsupport::ChildProcess child({"/usr/bin/prlimit", "--nofile=256:256", "--",
                                   std::string(FLIPPER_BINARY_DIR) + "/bin/flipper", "serve",
                                   "--set", "serve.port=0", "--set",
                                   "lexicon.path=" + dir + "/lexicon.sqlite", "--set",
                                   "lexicon.preload=", "--set", "serve.kernels=2"});
  // (It says it lowered the cap on stderr; the refusals below show the cap.)
  const std::string said = child.read_line(std::chrono::seconds(60));
  INFO(said);
  const auto at = said.find("127.0.0.1:");
  REQUIRE(at != std::string::npos);
  const int port = std::stoi(said.substr(at + 10));
  // 256 - 64 - 2 kernels x 4 = 184 connections at most.
  const double cpu0 = cpu_seconds(child.pid());
  Flood f = flood(port, 2, 10, 30);  // 300 connections from 10 addresses
  CHECK(f.sockets.size() == 300);
  CHECK(f.refused == 300 - 184);
  // Held for a second: the server waits, it does not spin.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  CHECK(cpu_seconds(child.pid()) - cpu0 < 0.5);
  f.sockets.clear();
  // Once they are gone, a client is served.
  httplib::Client c("127.0.0.1", port);
  c.set_read_timeout(30);
  bool served = false;
  for (int i = 0; i < 100 && !served; ++i) {  // the closes reach the server within a few ms
    auto res = c.Post("/api/v1/request", R"({"op":"state"})", "application/json");
    served = res && res->status == 200;
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(served);
  ::kill(child.pid(), SIGTERM);
  CHECK(child.finish() == 0);
}

TEST_CASE("out of descriptors, the server refuses and backs off instead of spinning") {
  StudioServer server(fresh_dir("nofile-emfile"), {"serve.kernels=2"});
  // Lowered after start: the cap (computed from the limit at start) no longer fits, so the
  // flood runs the server out of descriptors.
  rlimit limit{128, 128};
  REQUIRE(::prlimit(server.pid(), RLIMIT_NOFILE, &limit, nullptr) == 0);
  const double cpu0 = cpu_seconds(server.pid());
  Flood f = flood(server.port(), 2, 8, 25);  // 200 connections
  CHECK(f.sockets.size() == 200);
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // Spinning on EMFILE burns a core (~2 s of CPU in 2 s); backing off costs ~1 % of that.
  CHECK(cpu_seconds(server.pid()) - cpu0 < 0.5);
  f.sockets.clear();
  auto http = server.client();
  bool served = false;
  for (int i = 0; i < 100 && !served; ++i) {
    auto res = http.Post("/api/v1/request", R"({"op":"state"})", "application/json");
    served = res && res->status == 200;
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(served);
}

// POST {"op":"state"} without a session from `source`: the HTTP status.
int new_session_status(int port, const std::string& source) {
  RawSocket s(port, source);
  REQUIRE(s.connected());
  const std::string body = R"({"op":"state"})";
  REQUIRE(s.send("POST /api/v1/request HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                 "\r\nContent-Type: application/json\r\nContent-Length: " +
                 std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body));
  const std::string text = s.read_all(std::chrono::seconds(30));
  REQUIRE(text.size() > 12);
  return std::stoi(text.substr(9, 3));
}

TEST_CASE("guests from 60 addresses cannot take the sessions kept for logged-in users") {
  StudioServer server(fresh_dir("reserve"),
                      {"serve.max_sessions=50", "serve.reserved_sessions_percent=20"});
  server.add_account("ana", "a long password");
  int admitted = 0, refused = 0;
  for (int subnet = 1; subnet <= 10; ++subnet)
    for (int host = 1; host <= 6; ++host) {
      const int status = new_session_status(
          server.port(), "127.0." + std::to_string(subnet) + "." + std::to_string(host));
      admitted += status == 200;
      refused += status == 503;
    }
  CHECK(admitted == 40);  // 50 less the 20 % kept
  CHECK(refused == 20);
  // A logged-in user gets in; one more guest does not.
  auto http = server.client();
  const std::string as_ana = login(http, {{"name", "ana"}, {"password", "a long password"}});
  const Reply r = post(http, "", R"({"op":"state"})", cookie(as_ana));
  CHECK(r.status == 200);
  CHECK(r.user == "ana");
  CHECK(new_session_status(server.port(), "127.0.11.1") == 503);
}

using studio::RegistryLimits;
using studio::SessionEntry;
using studio::SessionRegistry;

std::shared_ptr<SessionEntry> add(SessionRegistry& r, const std::string& address,
                                  studio::Clock::time_point t, const std::string& account = "") {
  REQUIRE_FALSE(r.admit_new(address, t, !account.empty()));
  auto e = std::make_shared<SessionEntry>();
  e->address = address;
  e->account = account;
  return r.add(e, t);
}

TEST_CASE("subnets: /24 for IPv4 and mapped IPv4, /64 for IPv6") {
  CHECK(studio::subnet_of("10.1.2.3") == "10.1.2.0/24");
  CHECK(studio::subnet_of("::ffff:10.1.2.3") == "10.1.2.0/24");
  CHECK(studio::subnet_of("2001:db8:1:2:3:4:5:6") == "2001:db8:1:2::/64");
  CHECK(studio::subnet_of("::1") == "::/64");
  CHECK(studio::subnet_of("not an address") == "not an address");
}

TEST_CASE("guests per subnet: at most serve.sessions_per_subnet, accounts apart") {
  RegistryLimits l;
  l.sessions_per_subnet = 3;
  SessionRegistry r(l);
  const auto t = studio::Clock::now();
  add(r, "10.0.0.1", t);
  add(r, "10.0.0.1", t);
  add(r, "10.0.0.2", t);
  const auto refused = r.admit_new("10.0.0.3", t);
  REQUIRE(refused);
  CHECK(refused->status == 429);
  CHECK(refused->code == "too_many_sessions");
  CHECK_THAT(refused->message,
             Catch::Contains("10.0.0.0/24") && Catch::Contains("serve.sessions_per_subnet"));
  CHECK_FALSE(r.admit_new("10.0.1.1", t));        // another subnet
  CHECK_FALSE(r.admit_new("10.0.0.3", t, true));  // a logged-in user
}

TEST_CASE("reserved sessions: guests fill all but serve.reserved_sessions_percent") {
  RegistryLimits l;
  l.max_sessions = 10;
  l.reserved_percent = 20;  // guests: 8
  SessionRegistry r(l);
  const auto t = studio::Clock::now();
  for (int i = 0; i < 8; ++i) add(r, "10.0." + std::to_string(i) + ".1", t);
  const auto guest = r.admit_new("10.9.9.9", t);
  REQUIRE(guest);
  CHECK(guest->status == 503);
  CHECK_THAT(guest->message, Catch::Contains("kept for logged-in users"));
  add(r, "10.9.9.9", t, "ana");
  add(r, "10.9.9.9", t, "bob");
  const auto full = r.admit_new("10.9.9.9", t, true);  // 10 of 10, none idle
  REQUIRE(full);
  CHECK(full->status == 503);
  CHECK_THAT(full->message, Catch::Contains("serve.max_sessions"));
}

TEST_CASE("a full server evicts idle guests first, after serve.evict_after_s") {
  RegistryLimits l;
  l.max_sessions = 3;
  l.reserved_percent = 0;
  l.evict_after = std::chrono::seconds(120);
  l.idle = std::chrono::seconds(3600);
  SessionRegistry r(l);
  const auto t0 = studio::Clock::now();
  auto a = add(r, "10.0.0.1", t0);
  auto b = add(r, "10.0.0.2", t0, "ana");
  auto c = add(r, "10.0.0.3", t0 + std::chrono::seconds(100));
  // At 119 s nobody has been idle long enough.
  CHECK(r.admit_new("10.0.0.4", t0 + std::chrono::seconds(119)));
  CHECK(r.take_evicted().empty());
  // At 150 s the guest idle for 150 s goes; ana (an account, idle as long) and the guest idle for
  // 50 s stay.
  CHECK_FALSE(r.admit_new("10.0.0.4", t0 + std::chrono::seconds(150)));
  const auto evicted = r.take_evicted();
  REQUIRE(evicted.size() == 1);
  CHECK(evicted[0] == a);
  CHECK(r.find(b->token) == b);
  CHECK(r.find(c->token) == c);
}

TEST_CASE("new guest sessions are rated for all addresses together") {
  RegistryLimits l;
  l.new_guests_per_minute = 5;
  SessionRegistry r(l);
  const auto t = studio::Clock::now();
  for (int i = 0; i < 5; ++i) add(r, "10.0." + std::to_string(i) + ".1", t);
  const auto refused = r.admit_new("10.0.9.1", t);
  REQUIRE(refused);
  CHECK(refused->status == 503);
  CHECK_THAT(refused->message, Catch::Contains("serve.new_guests_per_minute"));
  CHECK_FALSE(r.admit_new("10.0.9.1", t, true));  // a logged-in user is not rated with guests
  // 5 a minute: one more 12 s later, not 11 s later.
  CHECK(r.admit_new("10.0.9.1", t + std::chrono::seconds(11)));
  CHECK_FALSE(r.admit_new("10.0.9.1", t + std::chrono::milliseconds(12001)));
}

}  // namespace
}  // namespace flipper::studiotest
