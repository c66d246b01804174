#pragma once
/// @file plugin_ref.hpp
/// The one way the kernel calls into a plugin. A PluginRef<T> holds a plugin object together
/// with who it is (kind, name, library file). `call(op, f)` runs `f(object)` and
///  - lets an sdk::Error through unchanged: its code is the plugin's answer (a world plugin's
///    bad_world, a planner's deadline_exceeded);
///  - turns any other exception into `plugin_error` with one message shape everywhere:
///    "plugin 'NAME' (FILE): OP: MESSAGE";
///  - reports the call's duration (wall and the calling thread's CPU time) to the process's
///    plugin-call observer, when one is set.
/// The loader builds the refs (it knows the file); a ref built from a bare object (tests,
/// in-process plugins) names the plugin "in-process".

#include <time.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "flipper/sdk/plugin.hpp"

namespace flipper::kernel {

/// Who a plugin is, for messages and timing.
struct PluginId {
  std::string kind;  ///< "planner"
  std::string name;  ///< "astar", or "in-process"
  std::string file;  ///< the library's absolute path; empty for an in-process object

  /// "plugin 'astar' (/path/libastar.so)", or "plugin 'in-process' (planner)".
  std::string label() const;
};

/// Where a plugin's calls run (plugins.isolation, docs/plugins-untrusted.md §6): on the calling
/// thread, or (the calls that change nothing the kernel keeps) in a child process each.
enum class Isolation { in_process, process };

/// How long one plugin call took: wall-clock time, and the CPU time of the thread that made it
/// (what a planner's "plan CPU time" is, unaffected by other processes on a busy machine).
struct PluginCallTime {
  std::chrono::nanoseconds wall{0}, thread_cpu{0};
};

/// Called after every plugin call when set: profiling and tracing hook up here, in one place.
using PluginCallObserver = void (*)(const PluginId& plugin, std::string_view op,
                                    const PluginCallTime& time);
/// Sets (or, with nullptr, clears) the process-wide observer; returns the previous one.
PluginCallObserver set_plugin_call_observer(PluginCallObserver observer);

/// The error for a failed call `op` of `plugin`, in the one message shape (see above). The
/// loader uses it for `create` and `describe`, which wrap every exception, sdk::Error included.
[[noreturn]] void throw_plugin_failure(const PluginId& plugin, std::string_view op,
                                       std::string_view message);

/// The plugin call a thread is in (the innermost), so that a process that dies inside a plugin
/// can say which (apps/record processes.hpp: `plugin_crashed` names plugin, operation, signal).
struct CurrentPluginCall {
  const PluginId* plugin = nullptr;
  std::string_view op;
};

namespace detail {
extern std::atomic<PluginCallObserver> g_plugin_call_observer;
/// This thread's current plugin call (two pointer stores per call; read by signal handlers).
inline thread_local CurrentPluginCall t_current_call;
/// Rethrows the exception in flight: sdk::Error as is, anything else as plugin_error.
[[noreturn]] void rethrow_plugin_failure(const PluginId& plugin, std::string_view op);

/// Reports the duration of one call on destruction (also when the call throws).
class CallTimer {
 public:
  CallTimer(const PluginId& plugin, std::string_view op)
      : observer_(g_plugin_call_observer.load(std::memory_order_relaxed)),
        plugin_(plugin),
        op_(op),
        outer_(t_current_call) {
    t_current_call = CurrentPluginCall{&plugin, op};
    if (observer_ != nullptr) {
      start_ = std::chrono::steady_clock::now();
      cpu_start_ = thread_cpu();
    }
  }
  ~CallTimer() {
    t_current_call = outer_;
    if (observer_ != nullptr)
      observer_(
          plugin_, op_,
          PluginCallTime{std::chrono::steady_clock::now() - start_, thread_cpu() - cpu_start_});
  }
  CallTimer(const CallTimer&) = delete;
  CallTimer& operator=(const CallTimer&) = delete;

 private:
  PluginCallObserver observer_;
  const PluginId& plugin_;
  std::string_view op_;
  CurrentPluginCall outer_;
  std::chrono::steady_clock::time_point start_{};
  std::chrono::nanoseconds cpu_start_{0};

  static std::chrono::nanoseconds thread_cpu() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec);
  }
};
}  // namespace detail

template <class T>
class PluginRef {
 public:
  PluginRef() = default;
  PluginRef(std::shared_ptr<T> object, PluginId id)
      : object_(std::move(object)), id_(std::make_shared<const PluginId>(std::move(id))) {}
  /// An in-process object (tests, benchmarks): named "in-process", no file.
  template <class U, class = std::enable_if_t<std::is_convertible_v<U*, T*>>>
  PluginRef(std::shared_ptr<U> object)  // NOLINT(google-explicit-constructor): a convenience
      : PluginRef(std::shared_ptr<T>(std::move(object)),
                  PluginId{sdk::kind_name(sdk::KindOf<std::remove_const_t<T>>::value), "in-process",
                           ""}) {}
  PluginRef(std::nullptr_t) {}  // NOLINT(google-explicit-constructor): "no such plugin"
  /// An object the caller keeps alive for as long as the ref is used (a wrapper on the stack).
  static PluginRef borrowed(T& object) {
    return PluginRef(std::shared_ptr<T>(std::shared_ptr<void>(), &object));
  }
  /// The same plugin seen through a const (or base) interface.
  template <class U, class = std::enable_if_t<std::is_convertible_v<U*, T*>>>
  PluginRef(const PluginRef<U>& other)  // NOLINT(google-explicit-constructor)
      : object_(other.shared()), id_(other.id_ptr()), isolation_(other.isolation()) {}

  explicit operator bool() const { return object_ != nullptr; }
  const PluginId& id() const { return *id_; }
  /// Where the calls that may be isolated run (checked_plan, checked_tour, checked_parse;
  /// isolation.hpp).
  Isolation isolation() const { return isolation_; }
  /// The same plugin, its isolable calls run as `isolation` says.
  PluginRef with_isolation(Isolation isolation) const {
    PluginRef r = *this;
    r.isolation_ = isolation;
    return r;
  }

  /// Runs `f(object)` as the plugin call `op` (see the file comment).
  template <class F>
  decltype(auto) call(std::string_view op, F&& f) const {
    const detail::CallTimer timer(*id_, op);
    try {
      return std::forward<F>(f)(*object_);
    } catch (...) {
      detail::rethrow_plugin_failure(*id_, op);
    }
  }

  /// The object itself, to hand it to another plugin (the parser scores with the scorer): calls
  /// the receiving plugin makes are covered by the guard of the call that handed it over.
  T* borrow() const { return object_.get(); }
  const std::shared_ptr<T>& shared() const { return object_; }
  const std::shared_ptr<const PluginId>& id_ptr() const { return id_; }

 private:
  std::shared_ptr<T> object_;
  std::shared_ptr<const PluginId> id_ = std::make_shared<const PluginId>();
  Isolation isolation_ = Isolation::in_process;
};

}  // namespace flipper::kernel
