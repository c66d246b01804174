// kernel::Executor: the core language's executor with the planner behind the kernel (kernel/exec,
// docs/architecture.md "What the kernel keeps"): an isolated planner's CPU time is charged to the
// execution's budget, and a path that breaks its contract is refused before the executor acts.
#include <catch2/catch.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/planner.hpp"

using namespace flipper;
using sdk::Cell;
using std::chrono::milliseconds;

namespace {

// A planner that spends `cpu` of CPU time on each plan, then answers a step to the first goal.
class SpinningPlanner : public sdk::Planner {
 public:
  milliseconds cpu{0};
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
  sdk::PlannerTraits do_traits() const override { return {}; }
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
