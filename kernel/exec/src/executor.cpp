// The planner as the kernel lets the executor see it: through its PluginRef, its answers checked.
#include "flipper/kernel/executor.hpp"

#include <utility>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/errors.hpp"

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
    : language::Executor(std::make_shared<CheckedPlanner>(std::move(planner)), limits) {}

}  // namespace flipper::kernel
