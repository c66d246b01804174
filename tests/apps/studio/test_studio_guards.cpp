// Boundaries the mutation sample (scripts/mutate) found unguarded: a key's queue holds exactly
// serve's max_queued_per_key waiting jobs (docs/studio.md §5), and a password of
// kMinPasswordLength characters is taken, one fewer refused (docs/accounts.md §2).
#include <catch2/catch.hpp>
#include <condition_variable>
#include <mutex>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/studio/accounts.hpp"
#include "scheduler.hpp"

namespace flipper::studio {

TEST_CASE("a key's queue holds max_queued_per_key waiting jobs, the next is refused") {
  SchedulerOptions o;
  o.workers = 1;
  o.max_queued_per_key = 3;
  Scheduler scheduler(o);
  std::mutex m;
  std::condition_variable cv;
  bool started = false, release = false;
  int ran = 0;
  // The first job runs (it is no longer waiting) and holds the only worker until released.
  REQUIRE(scheduler.submit("a", [&](int) {
    std::unique_lock lock(m);
    started = true;
    cv.notify_all();
    cv.wait(lock, [&] { return release; });
    ++ran;
  }));
  {
    std::unique_lock lock(m);
    REQUIRE(cv.wait_for(lock, std::chrono::seconds(10), [&] { return started; }));
  }
  const auto count = [&](int) {
    std::lock_guard lock(m);
    ++ran;
    cv.notify_all();
  };
  for (int i = 0; i < 3; ++i) CHECK(scheduler.submit("a", count));  // 3 waiting: the cap
  CHECK_FALSE(scheduler.submit("a", count));                        // the 4th is refused
  CHECK(scheduler.submit("b", count));  // another key has a queue of its own
  {
    std::lock_guard lock(m);
    release = true;
  }
  cv.notify_all();
  std::unique_lock lock(m);
  // Bound: five empty jobs; 10 s means they never ran.
  CHECK(cv.wait_for(lock, std::chrono::seconds(10), [&] { return ran == 5; }));
  CHECK(ran == 5);
}

TEST_CASE("a password of kMinPasswordLength characters is taken, one fewer is refused") {
  AccountStore store(":memory:");
  const std::string shortest(kMinPasswordLength, 'p');
  try {
    store.add("ana", shortest.substr(1), Role::user);
    FAIL("a password of " << kMinPasswordLength - 1 << " characters was taken");
  } catch (const sdk::Error& e) {
    CHECK(std::string(e.code()) == "weak_password");
    CHECK(std::string(e.what()) == "a password needs at least 8 characters");
  }
  store.add("ana", shortest, Role::user);
  CHECK(store.login("ana", shortest, std::chrono::hours(1)).has_value());
  const std::string longest(kMaxPasswordLength, 'p');
  store.add("bo", longest, Role::user);
  CHECK_THROWS_WITH(store.add("cy", longest + "p", Role::user),
                    "a password has at most 1024 characters");
}

}  // namespace flipper::studio
