#pragma once
/// @file executor.hpp
/// The core language's executor (language/exec: what programs mean) with the kernel between it
/// and the planner plugin (docs/plugins-untrusted.md): every path and tour it acts on comes
/// through the planner's PluginRef (a throwing plugin is plugin_error naming it; isolated calls
/// run in a child process) and is checked first (plugin_checks.hpp: invalid_plan), and the CPU
/// time of an isolated call is charged to the execution's budget as if this thread had done it.
/// An isolated planner's calls of one execution run in one child, recorded, and are replayed
/// in this process (docs/plugins-untrusted.md §6, "One child per execution").

#include <memory>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/language/executor.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::kernel {

using language::ExecLimits;

class Executor : public language::Executor {
 public:
  /// Every planner call goes through `planner` (a bare shared_ptr converts, named "in-process").
  explicit Executor(PluginRef<const sdk::Planner> planner, ExecLimits limits = {});
  using language::Executor::run;
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world,
                   const sdk::StopCondition& request) const override;

 private:
  PluginRef<const sdk::Planner> planner_;
};

}  // namespace flipper::kernel
