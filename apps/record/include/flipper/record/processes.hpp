#pragma once
/// @file processes.hpp
/// Running independent tasks (an experiment's variants) in parallel processes, at most `jobs` at a
/// time (docs/experiments.md §4). Each task runs in a child made with fork() from the calling
/// process, so it sees everything loaded before (a corpus read once) and shares nothing after:
/// results cannot depend on how many run beside it. Call it before any thread is started.

#include <cstddef>
#include <functional>
#include <vector>

namespace flipper::record {

/// The cores this process may run on (sched_getaffinity), at least 1.
int available_cores();

/// Runs task(0) .. task(count-1), each in its own child process, at most `jobs` at once, in
/// index order. A task's return value is its child's exit status; an exception escaping it is
/// reported by `on_exception` (in the child) and gives status 1. After a task fails, no further
/// task is started; those running are waited for. Returns the status of each task (-1: not
/// started; 128+N: killed by signal N). With jobs <= 1 or count <= 1 the tasks still run in
/// children, one at a time, so a task's effects never reach the caller's memory.
std::vector<int> run_in_processes(std::size_t count, int jobs,
                                  const std::function<int(std::size_t)>& task,
                                  const std::function<void(const std::exception&)>& on_exception);

}  // namespace flipper::record
