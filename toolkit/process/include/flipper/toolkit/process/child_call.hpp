#pragma once
/// @file child_call.hpp
/// A call in a forked child process, bounded, its answer streamed back (docs/architecture.md §1
/// "The toolkit"). The child inherits the caller's memory as it is at the fork, runs `body` on its
/// only thread, sends its answer with send_to_parent and stops itself; the parent reads what it
/// sends until it closes the pipe, within the limits, then measures the CPU time the body used
/// and kills it. Generic: it knows no plugin and no budget; the kernel isolates plugin calls with
/// it (kernel/plugin isolation.hpp, docs/plugins-untrusted.md §6).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <shared_mutex>
#include <string>
#include <string_view>

namespace flipper::toolkit::process {

struct ChildLimits {
  /// CPU time the child process may use, from its fork (SIGXCPU past it); max: unlimited.
  std::chrono::nanoseconds cpu = std::chrono::nanoseconds::max();
  /// When the parent stops waiting and kills the child (a wall-clock backstop); max: never.
  std::chrono::steady_clock::time_point kill_by = std::chrono::steady_clock::time_point::max();
  /// Set meanwhile: the child is killed (read every 50 ms); null: none.
  const std::atomic<bool>* cancel = nullptr;
  /// Bytes the child may send; more: it is killed (a bounded read).
  std::size_t max_bytes = std::size_t{256} << 20;
};

/// How a child's call ended.
enum class ChildEnd {
  answered,       ///< `body` returned (or the child exited with status 0): `bytes` is its answer
  exited,         ///< it exited with a status other than 0 (`status`), `body` unfinished
  signalled,      ///< a signal ended it (`signal`; SIGXCPU: past ChildLimits::cpu)
  cancelled,      ///< the cancel flag was set; it was killed
  wall_backstop,  ///< still running at kill_by; it was killed
  too_large,      ///< it sent more than max_bytes; it was killed
};

struct ChildCall {
  ChildEnd end = ChildEnd::answered;
  int signal = 0;     ///< the signal that ended it (signalled)
  int status = 0;     ///< its exit status (exited)
  std::string bytes;  ///< what it sent, in order (all of it but past max_bytes)
  /// CPU time the child used from the start of `body` (not the fork's cost before it, nor its
  /// exit, when it answered; to its end otherwise).
  std::chrono::nanoseconds cpu{0};
};

/// Runs `body` in a forked child (see the file comment) with `limits`. In the child: the default
/// action for the signals a crash raises, no signal blocked, killed when the calling thread
/// ends (PR_SET_PDEATHSIG), none of the parent's descriptors open but its answer's pipe; a
/// `body` that throws ends the child with status 4. Returns how the child ended; nullopt, having
/// run nothing, when no child can be started (no descriptor left for the pipe, no process left).
/// A child that sends nothing and returns from `body` has answered empty bytes.
std::optional<ChildCall> run_in_child(const ChildLimits& limits, const std::function<void()>& body);

/// In `body`, in the child: sends `bytes` to the parent at once. A parent no longer reading ends
/// the child (status 3). Throws std::logic_error outside a child of run_in_child.
void send_to_parent(std::string_view bytes);

/// A reader-writer lock of data a child may read: while alive, every fork of run_in_child holds
/// it shared, so that no child inherits it locked by a writer of another thread (it would wait for
/// ever). Not copyable.
class ReadAcrossFork {
 public:
  explicit ReadAcrossFork(std::shared_mutex& mutex);
  ~ReadAcrossFork();
  ReadAcrossFork(const ReadAcrossFork&) = delete;
  ReadAcrossFork& operator=(const ReadAcrossFork&) = delete;

 private:
  std::shared_mutex* mutex_;
};

}  // namespace flipper::toolkit::process
