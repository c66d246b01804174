#pragma once
/// @file version.hpp
/// Two numbers guard compatibility between the kernel and a plugin:
/// - FLIPPER_PLUGIN_ABI: an integer bumped whenever the descriptor layout or any interface vtable
///   changes (virtual functions added, removed or reordered), as LLVM does for pass plugins.
/// - The SDK semantic version: a plugin must have the same major, and its minor must be at most
///   the kernel's (a plugin built against a newer SDK minor may use what the kernel lacks).
/// Plus a build fingerprint (compiler, libstdc++ ABI, Boost and Eigen versions) that Boost.DLL
/// itself does not check: a mismatch there would crash instead of failing cleanly.
///
/// History: 1.1 — Parser::parse honours ParseRequest::stop in the non-virtual wrapper (and
/// StopCondition::expired); plugins built against 1.0 load unchanged.
/// Also 1.1: PlannerTraits::sampling (a field at the end; only the planner conformance kit reads
/// it, so a 1.0 planner's traits lose nothing the kernel uses).
/// 1.2 — IncrementalScorer, an optional interface a Scorer may also implement (found with
/// dynamic_cast; the Scorer vtable is unchanged): sparse additive weight changes.
/// 2.0 (ABI 2) — Rule no longer carries mutable use counters: the kernel owns them and passes
/// them to scorers in ScoreContext::usage (a read-only UsageCounters). Planner::plan and
/// Planner::tour decide the shared edge cases (empty goal set, start outside the bounds, a stop
/// that already fired, no tour points) before the virtual call, so planners cannot disagree on
/// them; the planner conformance kit checks the exact results. 1.x plugins must be rebuilt.
/// 2.1 — the kernel declares its config keys with ParamSchema: ParamType gains PathList,
/// DoubleList and Map (appended), ParamSchema gains add(), add_path_list(), add_double_list(),
/// add_map(), sections (a trailing member) and add_section(), Params gains get_double_list(),
/// and sdk::type_phrase(); validate_params words every message "config key '<full key>'" and
/// hints among a key's siblings. All additions: a 2.0 plugin loads unchanged.
/// 2.1.1 — no change to the library or its ABI: the installed package adds the toolkit
/// (Flipper::toolkit, a static library plugins link), the conformance kit of every kind with one
/// flipper_add_conformance_test call (flipper/testing/plugin_factory.hpp, core_scorer.hpp), and
/// a configure-time check of the build fingerprint. A 2.1.0 plugin loads unchanged.
/// 2.2 — ParamSchema::add_retired() and sdk::is_retired() (defined in the header: no new symbol,
/// no layout change): a retired key is refused by validate_params with its hint ("config key 'K'
/// is retired: ...") instead of as unknown. The planner contract states the tie rule among
/// equally near goals for every planner (not only optimal ones) and that budgets count work
/// (docs/planners.md); the planner conformance kit checks the tie rule and that a deterministic
/// planner answers the same whatever it was asked before. A 2.1 plugin loads unchanged.

#include <boost/version.hpp>

#define FLIPPER_PLUGIN_ABI 2
#define FLIPPER_SDK_VERSION_MAJOR 2
#define FLIPPER_SDK_VERSION_MINOR 2
#define FLIPPER_SDK_VERSION_PATCH 0

#define FLIPPER_STRINGIFY_IMPL(x) #x
#define FLIPPER_STRINGIFY(x) FLIPPER_STRINGIFY_IMPL(x)

#ifndef _GLIBCXX_USE_CXX11_ABI
#define FLIPPER_CXX11_ABI_VALUE 0
#else
#define FLIPPER_CXX11_ABI_VALUE _GLIBCXX_USE_CXX11_ABI
#endif

/// Build fingerprint compared by the loader; any difference refuses the plugin.
#define FLIPPER_BUILD_FINGERPRINT                                                \
  "gcc" FLIPPER_STRINGIFY(__GNUC__) ";cxx11abi=" FLIPPER_STRINGIFY(              \
      FLIPPER_CXX11_ABI_VALUE) ";boost=" FLIPPER_STRINGIFY(BOOST_VERSION) ";cxx" \
                                                                          "=" FLIPPER_STRINGIFY(__cplusplus)

namespace flipper::sdk {
inline namespace v1 {
struct SdkVersion {
  int major;
  int minor;
  int patch;
};
constexpr SdkVersion kSdkVersion{FLIPPER_SDK_VERSION_MAJOR, FLIPPER_SDK_VERSION_MINOR,
                                 FLIPPER_SDK_VERSION_PATCH};
}  // namespace v1
}  // namespace flipper::sdk
