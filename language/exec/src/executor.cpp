// Executor: runs one program on a copy of a world with a fresh interpreter and turns errors
// into Outcome::error (nothing of an erroneous execution is applied, §9).
#include "flipper/language/executor.hpp"

#include <optional>
#include <utility>

#include "flipper/sdk/errors.hpp"
#include "interpreter.hpp"

namespace flipper::language {

Executor::Executor(std::shared_ptr<const PlannerAccess> planner, ExecLimits limits)
    : planner_(std::move(planner)), limits_(limits) {
  if (!planner_) throw sdk::Error(sdk::codes::kInternal, "Executor needs a planner");
}

sdk::Outcome Executor::run(const sdk::Program& program, const sdk::WorldState& world) const {
  return run(program, world, sdk::StopCondition{});
}

sdk::Outcome Executor::run(const sdk::Program& program, const sdk::WorldState& world,
                           const sdk::StopCondition& request) const {
  sdk::Outcome out;
  out.world = world;
  auto error = [&](const std::string& code, const std::string& message) {
    out.world = world;
    out.trace.clear();
    out.warnings.clear();
    out.realizable = false;
    out.error = message;
    out.error_code = code;
  };
  if (!program || program->sort != sdk::Sort::Action) {
    error(sdk::codes::kExecution, "not a statement");
    return out;
  }
  if (!world.geometry || !world.rooms) {
    error(sdk::codes::kExecution, "the world state has no geometry");
    return out;
  }
  // Planner calls come back as sdk::Error (the kernel's plugin_error names the planner); anything
  // else is the executor's own failure, not the planner's.
  std::optional<detail::Interpreter> interp;
  try {
    interp.emplace(*planner_, limits_, world, request);
    out.realizable = interp->run(program, out.world, out.trace, out.warnings);
  } catch (const sdk::Error& e) {
    error(e.code(), e.what());
    out.stopped = sdk::stop_cause_of(e);
  } catch (const std::exception& e) {
    error(sdk::codes::kInternal, std::string("the executor failed: ") + e.what());
  } catch (...) {
    error(sdk::codes::kInternal, "the executor failed with an unknown exception");
  }
  if (interp) out.actions = interp->actions();
  return out;
}

}  // namespace flipper::language
