// A planner's calls in a child process each (kernel/isolation.hpp, docs/plugins-untrusted.md §6):
// the same answers and errors as in process, a crash turned into plugin_crashed naming plugin,
// call and signal, the CPU budget handed to the child and its CPU time charged back.
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/planner.hpp"

using namespace flipper;
using sdk::Cell;
using std::chrono::milliseconds;

namespace {

// One row of three free cells, 4-neighbourhood.
const auto kRow = std::make_shared<const sdk::Geometry>(
    2, Cell{0, 0, 0}, Cell{2, 0, 0}, std::vector<std::uint8_t>{1, 0, 1},
    std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
    std::vector<std::pair<std::string, Cell>>{});
const auto kOpenRow = std::make_shared<const sdk::Geometry>(
    2, Cell{0, 0, 0}, Cell{2, 0, 0}, std::vector<std::uint8_t>{1, 1, 1},
    std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
    std::vector<std::pair<std::string, Cell>>{});

class ScriptedPlanner : public sdk::Planner {
 public:
  std::function<sdk::PathResult(const sdk::StopCondition&)> plan_does;
  std::function<sdk::TourResult()> tour_does;

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest&,
                          const sdk::StopCondition& stop) const override {
    return plan_does(stop);
  }
  sdk::TourResult do_tour(const sdk::Geometry&, Cell, const std::vector<Cell>&,
                          const sdk::StopCondition&) const override {
    return tour_does();
  }
  sdk::PlannerTraits do_traits() const override { return {}; }
};

struct Fixture {
  std::shared_ptr<ScriptedPlanner> planner = std::make_shared<ScriptedPlanner>();
  kernel::PluginRef<const sdk::Planner> ref =
      kernel::PluginRef<const sdk::Planner>(
          std::static_pointer_cast<const sdk::Planner>(planner),
          kernel::PluginId{"planner", "scripted", "/plugins/libscripted.so"})
          .with_isolation(kernel::Isolation::process);
  sdk::Area goals{{2, 0, 0}};
  sdk::PathRequest request{{0, 0, 0}, &goals, nullptr};
};

// The code and message of what `f` throws ("(none)" when nothing).
std::pair<std::string, std::string> error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const sdk::Error& e) {
    return {e.code(), e.what()};
  }
  return {"(none)", ""};
}

void spin_cpu(milliseconds cpu) {
  const auto until = sdk::cpu_time() + cpu;
  volatile std::uint64_t n = 0;
  while (sdk::cpu_time() < until) n = n + 1;
}

// The CPU time that `calls` charge a wide (10 s) budget attached on this thread, given to them.
std::chrono::nanoseconds charged_by(const std::function<void(const sdk::StopCondition&)>& calls) {
  sdk::StopCondition wide = sdk::StopCondition::within_cpu(milliseconds(10000), milliseconds(0));
  const kernel::CpuCharge charge(wide);
  const auto left_before = wide.cpu_left();
  calls(wide);
  return left_before - wide.cpu_left();
}

}  // namespace

TEST_CASE("an isolated plan and tour give the in-process answers, checked", "[isolation]") {
  Fixture f;
  sdk::PathResult answer;
  answer.status = sdk::PlanStatus::found;
  answer.target = {2, 0, 0};
  answer.path = {{1, 0, 0}, {2, 0, 0}};
  answer.expansions = 12345678901ull;
  answer.message = std::string(100000, 'm');  // more than a pipe holds at once
  f.planner->plan_does = [&](const sdk::StopCondition&) { return answer; };
  const sdk::PathResult r = kernel::checked_plan(f.ref, *kOpenRow, f.request, {});
  CHECK(r.status == answer.status);
  CHECK(r.target == answer.target);
  CHECK(r.path == answer.path);
  CHECK(r.expansions == answer.expansions);
  CHECK(r.message == answer.message);
  // The same path on the row with a wall is refused after the child answered.
  CHECK(
      error_of([&] { (void)kernel::checked_plan(f.ref, *kRow, f.request, {}); }) ==
      std::pair<std::string, std::string>{
          "invalid_plan", "plugin 'scripted' (/plugins/libscripted.so): step 1 enters wall [1,0]"});

  f.planner->tour_does = [] {
    sdk::TourResult t;
    t.order = {2, 0, 1};
    t.length = 4.5;
    return t;
  };
  const std::vector<Cell> points{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const sdk::TourResult t = kernel::checked_tour(f.ref, *kOpenRow, {0, 0, 0}, points, {});
  CHECK(t.order == std::vector<std::size_t>{2, 0, 1});
  CHECK(t.length == 4.5);
}

TEST_CASE("an isolated call's exceptions arrive as in process", "[isolation]") {
  Fixture f;
  auto plan = [&] { (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, {}); };
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult {
    throw std::runtime_error("boom");
  };
  CHECK(error_of(plan) ==
        std::pair<std::string, std::string>{
            "plugin_error", "plugin 'scripted' (/plugins/libscripted.so): plan: boom"});
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult {
    throw sdk::StoppedError(sdk::StopCause::cpu_budget, "out of time");
  };
  try {
    plan();
    FAIL("no error");
  } catch (const sdk::StoppedError& e) {
    CHECK(e.cause() == sdk::StopCause::cpu_budget);
    CHECK(std::string(e.what()) == "out of time");
    CHECK(e.code() == "deadline_exceeded");
  }
}

TEST_CASE("an isolated call that crashes is plugin_crashed naming plugin, call and signal",
          "[isolation]") {
  Fixture f;
  const std::string label = "plugin 'scripted' (/plugins/libscripted.so): ";
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult {
    std::raise(SIGSEGV);
    return {};
  };
  CHECK(error_of([&] { (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, {}); }) ==
        std::pair<std::string, std::string>{"plugin_crashed", label + "plan: SIGSEGV"});
  f.planner->tour_does = []() -> sdk::TourResult { std::abort(); };
  CHECK(error_of([&] {
          (void)kernel::checked_tour(f.ref, *kOpenRow, {0, 0, 0}, {{2, 0, 0}}, {});
        }) == std::pair<std::string, std::string>{"plugin_crashed", label + "tour: SIGABRT"});
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult { std::_Exit(7); };
  CHECK(error_of([&] { (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, {}); }) ==
        std::pair<std::string, std::string>{
            "plugin_crashed", label + "plan: its process exited with status 7 and no answer"});
}

TEST_CASE("an isolated call gets the CPU budget left, and its CPU time is charged back",
          "[isolation]") {
  Fixture f;
  // A planner that honours its stop condition: it spins until the budget it was given is spent.
  f.planner->plan_does = [](const sdk::StopCondition& stop) {
    volatile std::uint64_t n = 0;
    while (!stop.expired()) n = n + 1;
    sdk::PathResult r;
    r.status = sdk::PlanStatus::stopped;
    r.message = sdk::to_string(stop.cause());
    return r;
  };
  sdk::StopCondition budget = sdk::StopCondition::within_cpu(milliseconds(300), milliseconds(0));
  const kernel::CpuCharge charge(budget);
  spin_cpu(milliseconds(100));  // 200 ms are left for the plan
  const auto parent_before = sdk::cpu_time();
  const sdk::PathResult r = kernel::checked_plan(f.ref, *kOpenRow, f.request, budget);
  const auto parent_used = sdk::cpu_time() - parent_before;
  CHECK(r.status == sdk::PlanStatus::stopped);
  CHECK(r.message == "cpu_budget");
  // The child's 200 ms are charged: the budget is spent although this thread used far less.
  CHECK(budget.cause() == sdk::StopCause::cpu_budget);
  CHECK(parent_used < milliseconds(100));

  // Without the charge attached the budget would still have ~200 ms left; with it, a plan that
  // spends 50 ms of its 10 s moves the deadline by at least those 50 ms.
  f.planner->plan_does = [](const sdk::StopCondition&) {
    spin_cpu(milliseconds(50));
    return sdk::PathResult{};
  };
  const auto charged = charged_by([&](const sdk::StopCondition& wide) {
    (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, wide);
  });
  CHECK(charged >= milliseconds(50));
  CHECK(charged < milliseconds(50 + 150));
}

// 256 MiB of this process's memory, written page by page in 4 KiB pages (no transparent huge
// pages): a fork copies its page table and the child's exit tears it down, as in a large server.
class Ballast {
 public:
  static constexpr std::size_t kBytes = std::size_t{256} << 20;
  Ballast() {
    memory_ = ::mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    REQUIRE(memory_ != MAP_FAILED);
    (void)::madvise(memory_, kBytes, MADV_NOHUGEPAGE);
    std::memset(memory_, 1, kBytes);
  }
  ~Ballast() { ::munmap(memory_, kBytes); }
  Ballast(const Ballast&) = delete;
  Ballast& operator=(const Ballast&) = delete;

 private:
  void* memory_;
};

TEST_CASE("an isolated call is charged its own work, not the fork's or the child's exit",
          "[isolation]") {
  Fixture f;
  // Plans that do nothing, first in this process as it is, then with 256 MiB more of it
  // written. Each fork copies the page table of that memory and each child's exit frees it:
  // 1-3 ms of CPU per call, which the budget once paid (a program of many plans ran out of a 2 s
  // budget on that alone). Now the request thread's time in the call is refunded and a child is
  // charged from just before the call until it stopped itself after answering: what the empty
  // plan touches (its copy-on-write faults), whatever the size of the process. What those faults
  // cost depends on the machine (0.15 ms a call on one 2-core VM, 1 ms on another whose page
  // faults cost ~10 us each), so the bound is on the difference the process's size makes.
  f.planner->plan_does = [](const sdk::StopCondition&) { return sdk::PathResult{}; };
  // The median charge of 21 such calls (one slow page fault moves no median).
  const auto median_charge = [&] {
    std::vector<std::chrono::nanoseconds> charges;
    for (int i = 0; i < 21; ++i)
      charges.push_back(charged_by([&](const sdk::StopCondition& wide) {
        (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, wide);
      }));
    std::sort(charges.begin(), charges.end());
    return charges[charges.size() / 2];
  };
  const auto small = median_charge();
  const Ballast ballast;
  const auto large = median_charge();
  INFO("an empty isolated plan charged " << small.count() << " ns, " << large.count()
                                         << " ns with 256 MiB more (medians of 21)");
  // Here: 0.0-0.25 ms more with the ballast in the Release build (what a fault costs grows a
  // little with the page table), -0.1 to 0.05 ms instrumented (2.4 ms a call); the old charge
  // added 9-18 ms. The bound of 2 ms sits between.
  CHECK(large - small < milliseconds(2));

  // The call's own work is charged whole, in a large process as in a small one.
  f.planner->plan_does = [](const sdk::StopCondition&) {
    spin_cpu(milliseconds(50));
    return sdk::PathResult{};
  };
  const auto charged_work = charged_by([&](const sdk::StopCondition& wide) {
    (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, wide);
  });
  CHECK(charged_work >= milliseconds(50));
  CHECK(charged_work < milliseconds(50 + 10));
}

TEST_CASE("an isolated call whose process exits without answering is charged what it spent",
          "[isolation]") {
  Fixture f;
  // The plugin ends its process itself, without the stop after an answer: its CPU time by
  // wait4 is charged, less what it had spent before the call.
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult {
    spin_cpu(milliseconds(40));
    ::_exit(0);
  };
  std::pair<std::string, std::string> error;
  const auto charged = charged_by([&](const sdk::StopCondition& wide) {
    error = error_of([&] { (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, wide); });
  });
  CHECK(error == std::pair<std::string, std::string>{
                     "plugin_crashed",
                     "plugin 'scripted' (/plugins/libscripted.so): plan: its process "
                     "exited with status 0 and no answer"});
  CHECK(charged >= milliseconds(40));
  CHECK(charged < milliseconds(40 + 20));
}

TEST_CASE("an isolated call that ignores its budget is ended 1 s of CPU after it (SIGXCPU)",
          "[isolation]") {
  Fixture f;
  f.planner->plan_does = [](const sdk::StopCondition&) -> sdk::PathResult {
    volatile std::uint64_t n = 0;
    for (;;) n = n + 1;
  };
  const auto stop = sdk::StopCondition::within_cpu(milliseconds(50), milliseconds(0));
  CHECK(error_of([&] { (void)kernel::checked_plan(f.ref, *kOpenRow, f.request, stop); }) ==
        std::pair<std::string, std::string>{
            "plugin_crashed",
            "plugin 'scripted' (/plugins/libscripted.so): plan: SIGXCPU (still "
            "running 1000 ms of CPU time after its budget was spent)"});
}
