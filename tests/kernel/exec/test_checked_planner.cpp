// kernel::Executor: the core language's executor with the planner behind the kernel (kernel/exec,
// docs/architecture.md "What the kernel keeps"): an isolated planner's CPU time is charged to the
// execution's budget, and a path that breaks its contract is refused before the executor acts;
// an isolated execution's planner calls run in one child and are replayed here
// (docs/plugins-untrusted.md §6, "One child per execution").
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/planner.hpp"

using namespace flipper;
using sdk::Cell;
using std::chrono::milliseconds;

namespace {

// Appends the process's id to `file` (none: nothing).
void append_pid(const std::string& file) {
  if (file.empty()) return;
  const std::string line = std::to_string(::getpid()) + "\n";
  const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0600);
  REQUIRE(::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size()));
  ::close(fd);
}

// A planner that spends `cpu` of CPU time on each plan, then answers a step to the first goal;
// each plan and traits call first appends the process's id to `pid_file` / `traits_file`; it
// crashes (SIGSEGV) when asked for `crash_at`, and ends its process (status 0) at `exit_at`.
class SpinningPlanner : public sdk::Planner {
 public:
  milliseconds cpu{0};
  std::string pid_file, traits_file;
  std::optional<Cell> crash_at, exit_at;
  std::function<sdk::PathResult(const sdk::PathRequest&)> answer = [](const sdk::PathRequest& r) {
    sdk::PathResult p;
    p.status = sdk::PlanStatus::found;
    p.target = *r.goals->begin();
    p.path = {p.target};  // a neighbour of the start in these tests
    return p;
  };

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest& request,
                          const sdk::StopCondition&) const override {
    append_pid(pid_file);
    if (crash_at && *request.goals->begin() == *crash_at) std::raise(SIGSEGV);
    if (exit_at && *request.goals->begin() == *exit_at) ::_exit(0);
    const auto until = sdk::cpu_time() + cpu;
    volatile std::uint64_t n = 0;
    while (sdk::cpu_time() < until) n = n + 1;
    return answer(request);
  }
  sdk::TourResult do_tour(const sdk::Geometry&, Cell, const std::vector<Cell>& points,
                          const sdk::StopCondition&) const override {
    sdk::TourResult t;
    for (std::size_t i = 0; i < points.size(); ++i) t.order.push_back(i);
    return t;
  }
  sdk::PlannerTraits do_traits() const override {
    append_pid(traits_file);
    return {};
  }
};

sdk::WorldState open_row() {
  sdk::WorldState w;
  w.geometry = std::make_shared<const sdk::Geometry>(
      2, Cell{0, 0, 0}, Cell{2, 0, 0}, std::vector<std::uint8_t>{1, 1, 1},
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
      std::vector<std::pair<std::string, Cell>>{});
  w.rooms = std::make_shared<const sdk::RoomMap>();
  return w;
}

kernel::PluginRef<const sdk::Planner> ref(const std::shared_ptr<SpinningPlanner>& p,
                                          kernel::Isolation isolation) {
  return kernel::PluginRef<const sdk::Planner>(std::static_pointer_cast<const sdk::Planner>(p),
                                               {"planner", "spinning", "/plugins/libspin.so"})
      .with_isolation(isolation);
}

// Six steps back and forth: six plans.
const char* const kSixVisits =
    "{{visit [1,0]};{visit [0,0]};{visit [1,0]};{visit [0,0]};{visit [1,0]};{visit [0,0]}}";

// Three plans, to [1,0], [0,0] and [2,0], with the planner isolated.
sdk::Outcome three_visits_isolated(const std::shared_ptr<SpinningPlanner>& planner) {
  return kernel::Executor(ref(planner, kernel::Isolation::process))
      .run(sdk::read_canonical("{{visit [1,0]};{visit [0,0]};{visit [2,0]}}"), open_row());
}

// A scratch file of this test process's own under build/tests/tmp, for the planner's pids.
std::string pid_file_named(const std::string& name) {
  const auto dir = std::filesystem::path(FLIPPER_BINARY_DIR) / "tests" / "tmp";
  std::filesystem::create_directories(dir);
  return (dir / (name + "-" + std::to_string(::getpid()) + ".txt")).string();
}

// A planner that writes its pid per plan call to a scratch file `name` of this process's own.
std::shared_ptr<SpinningPlanner> counted_planner(const std::string& name) {
  auto planner = std::make_shared<SpinningPlanner>();
  planner->pid_file = pid_file_named(name);
  return planner;
}

// The process ids the planner wrote, one per plan call (the file is removed).
std::vector<long> pids_in(const std::string& file) {
  std::vector<long> pids;
  std::ifstream in(file);
  for (long pid = 0; in >> pid;) pids.push_back(pid);
  ::unlink(file.c_str());
  return pids;
}

}  // namespace

TEST_CASE("an isolated planner's CPU time counts against execution.cpu_budget_ms",
          "[exec][isolation]") {
  auto planner = std::make_shared<SpinningPlanner>();
  planner->cpu = milliseconds(100);
  kernel::ExecLimits limits;
  limits.cpu_budget = milliseconds(350);  // three plans of 100 ms fit, four do not
  const auto program = sdk::read_canonical(kSixVisits);

  // In process the planner's time is this thread's: stopped after the fourth plan.
  const kernel::Executor in_process(ref(planner, kernel::Isolation::in_process), limits);
  const sdk::Outcome a = in_process.run(program, open_row());
  CHECK(a.error_code == sdk::codes::kDeadlineExceeded);
  CHECK(a.stopped == sdk::StopCause::cpu_budget);

  // In a child each, this thread spends less than the budget (forks and pipes); only the charge of
  // the children's CPU time can stop it, and it does, the same way.
  const kernel::Executor isolated(ref(planner, kernel::Isolation::process), limits);
  const auto before = sdk::cpu_time();
  const sdk::Outcome b = isolated.run(program, open_row());
  CHECK(sdk::cpu_time() - before < limits.cpu_budget);
  CHECK(b.error_code == sdk::codes::kDeadlineExceeded);
  CHECK(b.stopped == sdk::StopCause::cpu_budget);
  CHECK(b.world.robot == Cell{0, 0, 0});  // nothing of it applied

  // Within the budget both give the plan: six moves.
  limits.cpu_budget = milliseconds(5000);
  const sdk::Outcome c =
      kernel::Executor(ref(planner, kernel::Isolation::process), limits).run(program, open_row());
  CHECK_FALSE(c.error);
  CHECK(c.trace.size() == 6);
}

TEST_CASE("a path through a wall is refused before the executor moves the robot", "[exec]") {
  auto planner = std::make_shared<SpinningPlanner>();
  planner->answer = [](const sdk::PathRequest& r) {
    sdk::PathResult p;
    p.status = sdk::PlanStatus::found;
    p.target = Cell{2, 0, 0};
    p.path = {p.target};  // from [0,0], over [1,0]: not a step of the geometry
    (void)r;
    return p;
  };
  for (auto isolation : {kernel::Isolation::in_process, kernel::Isolation::process}) {
    const kernel::Executor exec(ref(planner, isolation));
    const sdk::Outcome o = exec.run(sdk::read_canonical("{visit [2,0]}"), open_row());
    CHECK(o.error_code == sdk::codes::kInvalidPlan);
    CHECK(o.error.value_or("").find("plugin 'spinning' (/plugins/libspin.so)") !=
          std::string::npos);
    CHECK(o.trace.empty());
    CHECK(o.world.robot == Cell{0, 0, 0});
  }
}

TEST_CASE("an isolated execution's planner calls run in one child, none when it plans nothing",
          "[exec][isolation]") {
  auto planner = counted_planner("exec_pids");
  const auto program = sdk::read_canonical(kSixVisits);
  const sdk::Outcome a =
      kernel::Executor(ref(planner, kernel::Isolation::in_process)).run(program, open_row());
  CHECK(pids_in(planner->pid_file) == std::vector<long>(6, ::getpid()));

  // The first call in a child of its own (the execution might plan only once), then, at the
  // second, the execution again from the start in one child that makes all six.
  const sdk::Outcome b =
      kernel::Executor(ref(planner, kernel::Isolation::process)).run(program, open_row());
  const std::vector<long> pids = pids_in(planner->pid_file);
  REQUIRE(pids.size() == 7);
  CHECK(pids[0] != ::getpid());
  CHECK(pids[1] != ::getpid());
  CHECK(pids[1] != pids[0]);
  CHECK(std::vector<long>(pids.begin() + 1, pids.end()) == std::vector<long>(6, pids[1]));
  CHECK_FALSE(b.error);
  CHECK(b.trace.size() == 6);
  CHECK(b.trace.size() == a.trace.size());
  CHECK(b.world.robot == a.world.robot);

  // A program with one planner call: its child, and no other.
  const sdk::Outcome once = kernel::Executor(ref(planner, kernel::Isolation::process))
                                .run(sdk::read_canonical("{visit [1,0]}"), open_row());
  CHECK(once.world.robot == Cell{1, 0, 0});
  const std::vector<long> once_pids = pids_in(planner->pid_file);
  REQUIRE(once_pids.size() == 1);
  CHECK(once_pids[0] != ::getpid());

  // A program without a planner call runs here, as in process: no child (the executor asks the
  // planner's traits as it starts, here only).
  planner->traits_file = pid_file_named("exec_traits_pids");
  sdk::WorldState row = open_row();
  row.geometry = std::make_shared<const sdk::Geometry>(
      2, Cell{0, 0, 0}, Cell{2, 0, 0}, std::vector<std::uint8_t>{1, 1, 1},
      std::vector<Cell>{{1, 0, 0}, {-1, 0, 0}},
      std::vector<std::pair<std::string, Cell>>{{"right", {1, 0, 0}}});
  const sdk::Outcome c = kernel::Executor(ref(planner, kernel::Isolation::process))
                             .run(sdk::read_canonical("{move right}"), row);
  CHECK(c.error.value_or("") == "");
  CHECK(c.world.robot == Cell{1, 0, 0});
  CHECK(pids_in(planner->pid_file).empty());
  CHECK(pids_in(planner->traits_file) == std::vector<long>{::getpid()});
}

TEST_CASE("a crash at an isolated execution's third planner call is that call's plugin_crashed",
          "[exec][isolation]") {
  auto planner = counted_planner("exec_crash_pids");
  planner->crash_at = Cell{2, 0, 0};
  const sdk::Outcome o = three_visits_isolated(planner);
  CHECK(o.error_code == "plugin_crashed");
  CHECK(o.error.value_or("") == "plugin 'spinning' (/plugins/libspin.so): plan: SIGSEGV");
  CHECK(o.world.robot == Cell{0, 0, 0});
  // The first call in a child of its own; then the recording child made three calls and died
  // in the third; the first two were replayed here, and the third has the child's death, not
  // made again.
  const std::vector<long> pids = pids_in(planner->pid_file);
  REQUIRE(pids.size() == 4);
  CHECK(pids[0] != pids[1]);
  CHECK(std::vector<long>(pids.begin() + 1, pids.end()) == std::vector<long>(3, pids[1]));
  CHECK(pids[1] != ::getpid());
}

TEST_CASE("a call the recording does not answer is made in a child of its own",
          "[exec][isolation]") {
  // The recording child ends, status 0, inside the third call: the tape ends there with no
  // error to give it, so that call is made again in a child of its own, which ends the same way:
  // the answer an isolated call that exits without answering has.
  auto planner = counted_planner("exec_exit_pids");
  planner->exit_at = Cell{2, 0, 0};
  const sdk::Outcome o = three_visits_isolated(planner);
  CHECK(o.error_code == "plugin_crashed");
  CHECK(o.error.value_or("") ==
        "plugin 'spinning' (/plugins/libspin.so): plan: its process exited with status 0 and no "
        "answer");
  // The probe's child, the recording child's three calls, the third call's own child.
  const std::vector<long> pids = pids_in(planner->pid_file);
  REQUIRE(pids.size() == 5);
  CHECK(pids[2] == pids[1]);
  CHECK(pids[3] == pids[1]);
  CHECK(pids[4] != pids[1]);
  CHECK(pids[4] != pids[0]);
  CHECK(pids[4] != ::getpid());
}

TEST_CASE("an isolated execution is charged its planner calls' CPU time once",
          "[exec][isolation]") {
  auto planner = std::make_shared<SpinningPlanner>();
  planner->cpu = milliseconds(40);  // six plans: 240 ms
  sdk::StopCondition request = sdk::StopCondition::within_cpu(milliseconds(10000), milliseconds(0));
  const kernel::CpuCharge charge(request);
  const auto left_before = request.cpu_left();
  const sdk::Outcome o = kernel::Executor(ref(planner, kernel::Isolation::process))
                             .run(sdk::read_canonical(kSixVisits), open_row(), request);
  const auto charged = left_before - request.cpu_left();
  CHECK_FALSE(o.error);
  CHECK(charged >= milliseconds(240));  // every replayed call's time
  // Not the recording child's as well (480), nor the first call the probe made (280).
  CHECK(charged < milliseconds(270));
}

TEST_CASE("a recording past its byte bound ends, and the calls after it are made one by one",
          "[exec][isolation]") {
  // Each plan answers no path with a 1 MiB message: 140 of them would send 140 MiB, past the
  // recording's bound (kernel::detail::kMaxTapeBytes, 128 MiB). The child stops before its 129th
  // call; the parent replays 128 and makes the other 12 in a child each, with the same answers.
  auto planner = counted_planner("exec_bound_pids");
  planner->answer = [](const sdk::PathRequest&) {
    sdk::PathResult p;
    p.status = sdk::PlanStatus::no_path;
    p.message = std::string(std::size_t{1} << 20, 'm');
    return p;
  };
  std::string text = "{";
  for (int i = 0; i < 140; ++i)
    text += (i == 0 ? "" : ";") + std::string("{if {possible {visit [2,0]}} {visit [1,0]}}");
  text += "}";
  STATIC_REQUIRE(kernel::detail::kMaxTapeBytes == std::size_t{128} << 20);
  const sdk::Outcome o = kernel::Executor(ref(planner, kernel::Isolation::process))
                             .run(sdk::read_canonical(text), open_row());
  CHECK(o.error.value_or("") == "");
  CHECK(o.world.robot == Cell{0, 0, 0});  // no visit was possible
  // The probe's child (its first call), the recording child's 128, then 12 children of one each.
  const std::vector<long> pids = pids_in(planner->pid_file);
  REQUIRE(pids.size() == 141);
  CHECK(std::vector<long>(pids.begin() + 1, pids.begin() + 129) == std::vector<long>(128, pids[1]));
  std::vector<long> rest(pids.begin() + 129, pids.end());
  std::sort(rest.begin(), rest.end());
  CHECK(std::adjacent_find(rest.begin(), rest.end()) == rest.end());  // each its own
  CHECK(std::find(rest.begin(), rest.end(), pids[1]) == rest.end());
}
