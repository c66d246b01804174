#pragma once
/// @file isolation.hpp
/// Plugin calls run in a child process (`plugins.isolation: process`, docs/plugins-untrusted.md
/// §6), so that a plugin that crashes or hangs spoils only the answer it was computing: the
/// request that made the call gets `plugin_crashed` naming plugin, operation and signal, and the
/// process (a server with other users' sessions) carries on.
///
/// A call is isolated by fork() (the toolkit's bounded child call,
/// flipper/toolkit/process/child_call.hpp): the child inherits the request as it is in memory (the
/// world, the request, the plugin object), makes the call on its only thread with the CPU budget
/// the request has left, writes the answer to a pipe and stops itself; the parent reads the answer
/// with a bound, charges the CPU time the child spent on the call to the request's budgets
/// (`CpuCharge`) and kills it, so that budgets still count work, never wall time, and the same
/// work whether isolated or not: the fork, what it costs the child before the call and the
/// child's exit are not charged (nor is the request thread's own time in call_in_child, which
/// is refunded). What the call changes in
/// the plugin object stays in the child: const calls are isolated as they are (a planner's plan
/// and tour, a parser's parse with its score_node calls); a scorer's learn sends the weights it
/// changed back as values, set in the parent (plugin_checks.hpp checked_learn).

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "flipper/kernel/plugin_ref.hpp"
#include "flipper/sdk/stop.hpp"

namespace flipper::kernel {

/// The stable error code of a call whose child process died (a signal, or killed for running
/// past its CPU budget or the wall-clock backstop).
inline constexpr const char* kPluginCrashed = "plugin_crashed";

/// While alive, CPU time that isolated plugin calls made on this thread spend in their child
/// processes is charged to `budget`: its cpu_deadline moves earlier by that much, exactly as if
/// the calling thread had done the work. Register every budget on the calling thread's CPU
/// clock that outlives a plugin call (a request's, an execution's). Not copyable.
class CpuCharge {
 public:
  CpuCharge() = default;
  explicit CpuCharge(sdk::StopCondition& budget) { attach(budget); }
  ~CpuCharge() { detach(); }
  CpuCharge(const CpuCharge&) = delete;
  CpuCharge& operator=(const CpuCharge&) = delete;
  /// Charges `budget` from now on, for the calling thread (replaces an earlier attach).
  void attach(sdk::StopCondition& budget);
  void detach();

 private:
  sdk::StopCondition* budget_ = nullptr;
};

/// Charges `cpu` to every budget attached on the calling thread (see CpuCharge); refund_cpu
/// gives it back (work thrown away, which a call in process would not have done).
void charge_cpu(std::chrono::nanoseconds cpu);
void refund_cpu(std::chrono::nanoseconds cpu);
/// What charge_cpu has charged on the calling thread so far, less what refund_cpu gave back.
std::chrono::nanoseconds charged_cpu();

namespace detail {

/// Runs `work` in a forked child as the call `op` of `plugin` (see the file comment). `work`
/// gets the child's stop condition (the budget `stop` has left, on the child's own CPU clock,
/// and `stop`'s wall backstop) and returns the answer's bytes; whatever it throws is carried to
/// the parent and rethrown there as PluginRef::call would (sdk::Error as is, a StoppedError
/// with its cause, anything else as plugin_error). Returns the answer's bytes. Throws
/// sdk::Error(plugin_crashed, "plugin 'NAME' (FILE): OP: SIGNAL ...") when the child dies,
/// StoppedError(cancelled) when `stop`'s cancel flag is set meanwhile (the child is killed).
/// Returns nullopt, having run nothing, when no child can be started (no descriptor left for
/// the pipe, no process left): the caller then makes the call in process. When it throws and
/// `received` is given, `*received` holds what the child had sent by then (send_part). With
/// `charge` false the child's CPU time is not charged (a recording child's calls are charged
/// one by one when they are replayed).
std::optional<std::string> call_in_child(
    const PluginId& plugin, std::string_view op, const sdk::StopCondition& stop,
    const std::function<std::string(const sdk::StopCondition&)>& work,
    std::string* received = nullptr, bool charge = true);

/// In `work`, in the child: sends `bytes` to the parent at once, as the first part of the answer
/// (`work` then returns the rest), so that what a call answers in parts (checked_parses' series)
/// reaches the parent as it is made, and a child that dies midway has sent the parts before it.
/// A `work` that sends parts must not throw after them. Throws std::logic_error outside a child.
void send_part(std::string_view bytes);

/// In a catch block, in a child: the exception in flight as the bytes of an
/// sdk::host::CallFailure (rethrow_plugin_failure's error: an sdk::Error as is, with its stop
/// cause, anything else as plugin_error); nullopt when even that cannot be made.
std::optional<std::string> failure_bytes(const PluginId& plugin, std::string_view op);

/// In the parent: throws what failure_bytes encoded, as the call in process would have thrown it
/// (a StoppedError with its cause, an sdk::Error with its code); plugin_crashed ("its process
/// sent a malformed answer") when `bytes` are not one CallFailure.
[[noreturn]] void throw_failure(const PluginId& plugin, std::string_view op,
                                std::string_view bytes);

/// Rethrows `end`, what call_in_child threw for a child that died making the call "execute" (a
/// recording of an execution's planner calls), as the error of the call `op` it died in.
[[noreturn]] void rethrow_as_call(const std::exception_ptr& end, const PluginId& plugin,
                                  std::string_view op);

/// How much more CPU time than its budget a child may use before it is killed (SIGXCPU): a
/// plugin that honours its stop condition answers `stopped` well within it.
inline constexpr std::chrono::milliseconds kCpuGrace{1000};

/// Bytes of an answer a child may send (more is plugin_crashed: a bounded read).
inline constexpr std::size_t kMaxAnswerBytes = std::size_t{256} << 20;
/// Bytes a recording child sends before it stops (docs/plugins-untrusted.md §6): the calls
/// after them are made one by one, and the call in progress has the rest of kMaxAnswerBytes.
inline constexpr std::size_t kMaxTapeBytes = kMaxAnswerBytes / 2;

}  // namespace detail
}  // namespace flipper::kernel
