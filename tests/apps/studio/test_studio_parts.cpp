// The studio's parts on their own, with exact expectations: the rate limit's burst cap, the
// scheduler's order, the Host and Origin checks, world paths, names in headers.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <condition_variable>
#include <mutex>

#include "api.hpp"
#include "cookies.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/studio/accounts.hpp"
#include "host_policy.hpp"
#include "product_schema.hpp"
#include "registry.hpp"
#include "scheduler.hpp"
#include "studio_ops.hpp"

namespace flipper::studio {
namespace {

TEST_CASE("idle time refills a session's request bucket up to the burst, never beyond") {
  RegistryLimits limits;
  limits.rate_per_second = 1;
  limits.rate_burst = 3;
  SessionRegistry registry(limits);
  const auto t0 = Clock::now();
  auto e = registry.add(std::make_shared<SessionEntry>(), t0);
  for (int i = 0; i < 3; ++i) CHECK(registry.admit(*e, t0));
  CHECK_FALSE(registry.admit(*e, t0));  // the burst is spent
  // A thousand idle seconds bank three requests, not a thousand.
  const auto later = t0 + std::chrono::seconds(1000);
  for (int i = 0; i < 3; ++i) CHECK(registry.admit(*e, later));
  CHECK_FALSE(registry.admit(*e, later));
  // One second later: one more.
  CHECK(registry.admit(*e, later + std::chrono::seconds(1)));
  CHECK_FALSE(registry.admit(*e, later + std::chrono::seconds(1)));
}

TEST_CASE("new sessions per address: at most serve.sessions_per_address open") {
  RegistryLimits limits;
  limits.sessions_per_address = 2;
  SessionRegistry registry(limits);
  const auto now = Clock::now();
  for (int i = 0; i < 2; ++i) {
    REQUIRE_FALSE(registry.admit_new("10.0.0.1", now));
    auto e = std::make_shared<SessionEntry>();
    e->address = "10.0.0.1";
    registry.add(e, now);
  }
  const auto refused = registry.admit_new("10.0.0.1", now);
  REQUIRE(refused);
  CHECK(refused->status == 429);
  CHECK(refused->code == "too_many_sessions");
  CHECK_FALSE(registry.admit_new("10.0.0.2", now));  // another address
}

TEST_CASE("a free worker takes the session that used the least CPU time") {
  SchedulerOptions o;
  o.workers = 1;
  o.cpu_ms_per_s = 1;  // hardly refills during the test: the order is set by what was used
  o.cpu_burst_ms = 1000;
  Scheduler scheduler(o);
  std::mutex m;
  std::condition_variable cv;
  bool release = false;
  std::vector<std::string> order;
  const auto burn = [](double ms) {
    const double until = thread_cpu_ms() + ms;
    while (thread_cpu_ms() < until) {
    }
  };
  // heavy's first job burns 30 ms of CPU, then waits until everything else is queued.
  scheduler.submit("heavy", [&](int) {
    burn(30);
    std::unique_lock lock(m);
    order.push_back("heavy-1");
    cv.notify_all();
    cv.wait(lock, [&] { return release; });
  });
  scheduler.submit("heavy", [&](int) {
    std::lock_guard lock(m);
    order.push_back("heavy-2");
    cv.notify_all();
  });
  scheduler.submit("light", [&](int) {
    std::lock_guard lock(m);
    order.push_back("light-1");
    cv.notify_all();
  });
  {
    std::unique_lock lock(m);
    cv.wait_for(lock, std::chrono::seconds(10), [&] { return order.size() == 1; });
    release = true;
  }
  cv.notify_all();
  {
    std::unique_lock lock(m);
    cv.wait_for(lock, std::chrono::seconds(10), [&] { return order.size() == 3; });
  }
  // heavy queued its second job before light, but light has used nothing.
  CHECK(order == std::vector<std::string>{"heavy-1", "light-1", "heavy-2"});
  CHECK(scheduler.allowance_ms("heavy") < 1000 - 29);
  CHECK(scheduler.allowance_ms("light") > 999);
}

// A gate the test opens; jobs wait at it and say they arrived.
struct Gate {
  std::mutex m;
  std::condition_variable cv;
  bool open = false;
  std::vector<std::string> log;
  void note(const std::string& what) {
    std::lock_guard lock(m);
    log.push_back(what);
    cv.notify_all();
  }
  void wait_open() {
    std::unique_lock lock(m);
    cv.wait(lock, [&] { return open; });
  }
  void release() {
    std::lock_guard lock(m);
    open = true;
    cv.notify_all();
  }
  bool wait_for(std::size_t n) {
    std::unique_lock lock(m);
    return cv.wait_for(lock, std::chrono::seconds(20), [&] { return log.size() >= n; });
  }
  bool saw(const std::string& what) {
    std::lock_guard lock(m);
    return std::find(log.begin(), log.end(), what) != log.end();
  }
};

TEST_CASE("heavy sessions leave the reserved worker to cheap ones") {
  SchedulerOptions o;
  o.workers = 2;
  o.reserve = 1;
  o.heavy_ms = 5;
  Scheduler scheduler(o);
  Gate g;
  // h1 and h2 become heavy: one job each burning 12 ms of CPU (cost averages to >= 6 ms).
  for (const char* key : {"h1", "h2"})
    scheduler.submit(key, [&, key](int) {
      const double until = thread_cpu_ms() + 12;
      while (thread_cpu_ms() < until) {
      }
      g.note(std::string(key) + "-burnt");
    });
  REQUIRE(g.wait_for(2));
  // h1 holds the one heavy slot; h2 must wait for it although a worker is free, the light
  // session must not.
  scheduler.submit("h1", [&](int) {
    g.note("h1-running");
    g.wait_open();
  });
  REQUIRE(g.wait_for(3));
  scheduler.submit("h2", [&](int) { g.note("h2-ran"); });
  scheduler.submit("light", [&](int) { g.note(g.saw("h2-ran") ? "light-after-h2" : "light"); });
  REQUIRE(g.wait_for(4));
  CHECK(g.saw("light"));
  CHECK_FALSE(g.saw("h2-ran"));
  g.release();
  REQUIRE(g.wait_for(5));
  CHECK(g.saw("h2-ran"));
}

TEST_CASE("a pinned session runs on its worker only") {
  SchedulerOptions o;
  o.workers = 2;
  Scheduler scheduler(o);
  Gate g;
  std::atomic<int> pinned_ran_on{-1};
  // The pinned key's first job holds worker 0; its second job waits for worker 0 although
  // worker 1 is free and runs a job of another key meanwhile.
  scheduler.submit(
      "pinned",
      [&](int worker) {
        g.note("first-on-" + std::to_string(worker));
        g.wait_open();
      },
      0);
  REQUIRE(g.wait_for(1));
  CHECK(g.saw("first-on-0"));
  scheduler.submit(
      "pinned",
      [&](int worker) {
        pinned_ran_on = worker;
        g.note("second");
      },
      0);
  scheduler.submit("other", [&](int worker) { g.note("other-on-" + std::to_string(worker)); });
  REQUIRE(g.wait_for(2));
  CHECK(g.saw("other-on-1"));
  CHECK_FALSE(g.saw("second"));
  g.release();
  REQUIRE(g.wait_for(3));
  CHECK(pinned_ran_on == 0);
}

TEST_CASE("a spent CPU allowance holds a session's next request back") {
  SchedulerOptions o;
  o.workers = 1;
  o.cpu_ms_per_s = 100;
  o.cpu_burst_ms = 20;
  Scheduler scheduler(o);
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::pair<std::string, Clock::time_point>> ran;
  const auto record = [&](const char* name) {
    std::lock_guard lock(m);
    ran.emplace_back(name, Clock::now());
    cv.notify_all();
  };
  scheduler.submit("heavy", [&](int) {
    const double until = thread_cpu_ms() + 40;  // 20 ms over the allowance
    while (thread_cpu_ms() < until) {
    }
    record("heavy-1");
  });
  scheduler.submit("heavy", [&](int) { record("heavy-2"); });
  std::unique_lock lock(m);
  REQUIRE(cv.wait_for(lock, std::chrono::seconds(10), [&] { return ran.size() == 2; }));
  // -20 ms refills at 100 ms/s: the second job waits at least 200 ms.
  CHECK(ran[1].second - ran[0].second >= std::chrono::milliseconds(190));
}

TEST_CASE("the Host must be a served name, the Origin one of them") {
  const HostPolicy p("127.0.0.1", 8410, {"studio.example", "other.example:9000"});
  CHECK(p.allows_host("127.0.0.1:8410"));
  CHECK(p.allows_host("localhost:8410"));
  CHECK(p.allows_host("LOCALHOST:8410"));
  CHECK(p.allows_host("studio.example:8410"));
  CHECK(p.allows_host("other.example:9000"));
  CHECK_FALSE(p.allows_host("other.example:8410"));
  CHECK_FALSE(p.allows_host("127.0.0.1:8411"));
  CHECK_FALSE(p.allows_host("127.0.0.1"));  // port 80
  CHECK_FALSE(p.allows_host("evil.com:8410"));
  CHECK_FALSE(p.allows_host(""));
  HttpRequest r;
  r.host = "evil.com:8410";
  r.origin = "http://evil.com:8410";  // agrees with Host: a rebinding page
  CHECK_FALSE(p.allows_origin(r));
  r.origin = "http://localhost:8410";
  CHECK(p.allows_origin(r));
  r.origin = "http://localhost:8410/x";
  CHECK_FALSE(p.allows_origin(r));
  r.origin = "null";
  CHECK_FALSE(p.allows_origin(r));
  r.origin.clear();
  CHECK(p.allows_origin(r));  // no browser
  r.sec_fetch_site = "cross-site";
  CHECK_FALSE(p.allows_origin(r));
  const HostPolicy any("0.0.0.0", 80, {});
  CHECK_FALSE(any.allows_host("0.0.0.0"));
  CHECK(any.allows_host("localhost"));
  const HostPolicy v6("::1", 8410, {});
  CHECK(v6.allows_host("[::1]:8410"));
  // The router's guard: a served Host passes untouched, any other is refused 421 wrong_host
  // with the Host named; an empty Host too.
  HttpRequest served;
  served.host = "localhost:8410";
  HttpReply untouched;
  CHECK_FALSE(p.refuse(served, untouched));
  CHECK(untouched.status == 200);
  CHECK(untouched.body.empty());
  for (const std::string host : {"evil.com:8410", "127.0.0.1:8411", "other.example:8410", ""}) {
    INFO("Host: " << host);
    HttpRequest wrong;
    wrong.host = host;
    HttpReply reply;
    CHECK(p.refuse(wrong, reply));
    CHECK(reply.status == 421);
    const auto body = nlohmann::json::parse(reply.body);
    CHECK(body["error"]["code"] == "wrong_host");
    CHECK_THAT(body["error"]["message"].get<std::string>(),
               Catch::StartsWith("this server does not answer to Host '" + host + "'"));
  }
}

TEST_CASE("a world path is inside its folder by components, not by prefix") {
  CHECK(path_inside("/srv/worlds/a.json", "/srv/worlds"));
  CHECK(path_inside("/srv/worlds/sub/a.json", "/srv/worlds/"));
  CHECK_FALSE(path_inside("/srv/worlds-x/a.json", "/srv/worlds"));  // a sibling folder
  CHECK_FALSE(path_inside("/srv/world", "/srv/worlds"));
  CHECK_FALSE(path_inside("/etc/passwd", "/srv/worlds"));
}

TEST_CASE("names reach headers only in a safe form") {
  CHECK(header_safe("ana") == "ana");
  CHECK(header_safe("guest-12") == "guest-12");
  CHECK(header_safe(std::string("ana\0x", 5)) == "ana%00x");
  CHECK(header_safe("a\r\nSet-Cookie: x") == "a%0D%0ASet-Cookie%3A%20x");
  CHECK(login_cookie("a=1; flipper_login=abc; b=2") == "abc");
  CHECK(login_cookie("flipper_login=abc") == "abc");
  CHECK(login_cookie("xflipper_login=abc") == "");
}

TEST_CASE("account names: printable, bounded, never a guest's") {
  CHECK_FALSE(name_problem("ana"));
  CHECK_FALSE(name_problem(std::string(32, 'a')));
  CHECK(name_problem(std::string(33, 'a')));
  CHECK(name_problem(""));
  CHECK(name_problem(std::string("ana\0x", 5)));
  CHECK(name_problem("ana\r\n"));
  CHECK(name_problem("guest-1"));
  CHECK(name_problem("anonymous"));
  CHECK(name_problem("ä"));
}

TEST_CASE("an in-memory lexicon keeps its accounts in memory, never in the working folder",
          "[studio][accounts]") {
  CHECK(accounts_path(kernel::Config::load(std::nullopt, {"lexicon.path=:memory:"})) == ":memory:");
  CHECK(accounts_path(kernel::Config::load(std::nullopt, {"lexicon.path=/x/y/lexicon.sqlite"})) ==
        "/x/y/accounts.sqlite");
  CHECK(accounts_path(kernel::Config::load(
            std::nullopt, {"lexicon.path=:memory:", "serve.accounts=/z/a.sqlite"})) ==
        "/z/a.sqlite");
}

}  // namespace
}  // namespace flipper::studio
