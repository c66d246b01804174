// The planner as the kernel lets the executor see it: through its PluginRef, its answers checked.
#include "flipper/kernel/executor.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/process/call_tape.hpp"

namespace flipper::kernel {
namespace {

class CheckedPlanner final : public language::PlannerAccess {
 public:
  explicit CheckedPlanner(PluginRef<const sdk::Planner> planner) : planner_(std::move(planner)) {
    if (!planner_) throw sdk::Error(sdk::codes::kInternal, "Executor needs a planner");
  }
  sdk::PlannerTraits traits() const override {
    return planner_.call("traits", [](const sdk::Planner& p) { return p.traits(); });
  }
  sdk::PathResult plan(const sdk::Geometry& geometry, const sdk::PathRequest& request,
                       sdk::StopCondition& stop) const override {
    const CpuCharge charge(stop);  // an isolated call's CPU time counts against `stop`
    return checked_plan(planner_, geometry, request, stop);
  }
  sdk::TourResult tour(const sdk::Geometry& geometry, sdk::Cell start,
                       const std::vector<sdk::Cell>& points,
                       sdk::StopCondition& stop) const override {
    const CpuCharge charge(stop);
    return checked_tour(planner_, geometry, start, points, stop);
  }

 private:
  PluginRef<const sdk::Planner> planner_;
};

}  // namespace

Executor::Executor(PluginRef<const sdk::Planner> planner, ExecLimits limits)
    : language::Executor(std::make_shared<CheckedPlanner>(planner), limits),
      planner_(std::move(planner)) {}

// docs/plugins-untrusted.md §6, "One child per execution".
sdk::Outcome Executor::run(const sdk::Program& program, const sdk::WorldState& world,
                           const sdk::StopCondition& request) const {
  using toolkit::process::CallTape;
  if (planner_.isolation() != Isolation::process || CallTape::current() != nullptr)
    return language::Executor::run(program, world, request);
  // First as without a tape, up to a second planner call: a program that plans nothing forks
  // nothing, one that plans once one child for it.
  const auto probe_start = sdk::cpu_time() + charged_cpu();
  {
    const CallTape probe(CallTape::Mode::probe);
    sdk::Outcome out = language::Executor::run(program, world, request);
    if (!probe.missed()) return out;
  }
  refund_cpu(sdk::cpu_time() + charged_cpu() - probe_start);  // a run thrown away
  // Then in one child, within the tighter of the request's and the execution's limits, each
  // planner call made in process there and recorded.
  sdk::StopCondition bound = request;
  if (request.cpu_left() > limits().cpu_budget) {
    bound.cpu_clock = CLOCK_THREAD_CPUTIME_ID;
    bound.cpu_deadline = sdk::cpu_time() + limits().cpu_budget;
  }
  bound.deadline = std::min(request.deadline, std::chrono::steady_clock::now() + limits().deadline);
  std::string tape;
  std::exception_ptr end;
  try {
    auto record = [&](const sdk::StopCondition& child_stop) {
      const CallTape recording(CallTape::Mode::record);
      (void)language::Executor::run(program, world, child_stop);
      return std::string();
    };
    if (auto bytes = detail::call_in_child(planner_.id(), "execute", bound, record, &tape, false))
      tape = std::move(*bytes);
  } catch (...) {  // it died: the calls it answered are replayed, the one it died in ends so
    end = std::current_exception();
    if (!tape.empty() && tape.front() == 'A') tape.erase(0, 1);
  }
  // Then here again, each call answered from the record, charged its CPU time and checked as an
  // isolated call's answer is; a call the record does not have forks a child of its own.
  const CallTape replay(CallTape::Mode::replay, std::move(tape), end);
  return language::Executor::run(program, world, request);
}

}  // namespace flipper::kernel
