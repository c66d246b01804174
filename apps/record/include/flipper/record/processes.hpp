#pragma once
/// @file processes.hpp
/// Running independent tasks (an experiment's variants, a benchmark's cells) in child processes,
/// at most `jobs` at a time (docs/experiments.md §4). Each task runs in a child made with fork()
/// from the calling process, so it sees everything loaded before (a corpus read once) and shares
/// nothing after: results cannot depend on how many run beside it, and a plugin that crashes or
/// hangs in one task costs that task only (docs/experiments.md §6, "Crashed and hung plugins").
/// Call it before any thread is started.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace flipper::record {

/// The cores this process may run on (sched_getaffinity), at least 1.
int available_cores();

/// "SIGSEGV", "SIGABRT", ... ("signal N" for one without a name here).
std::string signal_name(int signal);

/// How one task's child ended.
struct ChildExit {
  int status = -1;        ///< exit status; 128+N when killed by signal N; -1: not started
  int signal = 0;         ///< the signal that ended it (0: it exited)
  bool backstop = false;  ///< killed by the wall-clock backstop (a hang)
  /// The plugin call it was in when it died ("plugin 'evil_planner' (FILE): plan"), or "".
  std::string during;
  /// What an exception escaping the task said ("[code] message"), or "".
  std::string message;

  bool ok() const { return status == 0; }
  /// `wall_backstop` for a hang, `plugin_crashed` for a signal inside a plugin call, `crashed`
  /// for a signal elsewhere, `failed` for a non-zero exit, `not_started`, or `ok`.
  std::string kind() const;
  /// One line for people: "plugin_crashed: plugin 'evil_planner' (FILE): plan: SIGSEGV".
  std::string describe() const;
};

struct IsolationOptions {
  int jobs = 1;  ///< children at once (at least 1)
  /// Wall-clock seconds a child may run before it is killed (SIGALRM; 0: no backstop). A far
  /// backstop against hangs only: every limit that can change a result counts work or CPU time.
  int wall_backstop_s = 0;
  /// Whether tasks still start after one failed (false: those running are waited for only).
  bool keep_going = true;
  /// Called in the calling process as each task's child ends (progress lines), when set.
  std::function<void(std::size_t task, const ChildExit&)> on_exit;
};

/// Runs task(0) .. task(count-1), each in its own child process, at most options.jobs at once,
/// in index order. A task's return value is its child's exit status; an exception escaping it
/// gives status 1, its text in ChildExit::message (and `on_exception`, in the child, when set).
/// A child that dies of a signal inside a plugin call names the call (ChildExit::during).
std::vector<ChildExit> run_isolated(
    std::size_t count, const IsolationOptions& options, const std::function<int(std::size_t)>& task,
    const std::function<void(const std::exception&)>& on_exception = nullptr);

/// In a task's child: starts its wall-clock backstop again (a task of several steps, each
/// allowed options.wall_backstop_s). Does nothing outside such a child.
void restart_backstop();

/// run_isolated with no backstop that starts nothing after a failure; the statuses only.
std::vector<int> run_in_processes(std::size_t count, int jobs,
                                  const std::function<int(std::size_t)>& task,
                                  const std::function<void(const std::exception&)>& on_exception);

}  // namespace flipper::record
