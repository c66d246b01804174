#pragma once
// Whether this front end is built with a sanitizer (the test suite's build-fuzz/ tree,
// docs/testing.md "Fuzzing and sanitizers"), for the few places that behave differently there.
#include "flipper/kernel/runtime.hpp"

namespace flipper::cli {

// GCC says __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang __has_feature (GCC 12 has none).
#if defined(__has_feature)
#define FLIPPER_CLI_HAS_FEATURE(x) __has_feature(x)
#else
#define FLIPPER_CLI_HAS_FEATURE(x) 0
#endif
#if defined(__SANITIZE_ADDRESS__) || FLIPPER_CLI_HAS_FEATURE(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#if defined(__SANITIZE_THREAD__) || FLIPPER_CLI_HAS_FEATURE(thread_sanitizer)
inline constexpr bool kThreadSanitizer = true;
#else
inline constexpr bool kThreadSanitizer = false;
#endif
#undef FLIPPER_CLI_HAS_FEATURE

/// The isolation a server gives `plugins.isolation: auto` (docs/plugins-untrusted.md §6, "Where
/// it is on"): `process`, except under AddressSanitizer. clang 14's ASan installs no fork
/// handlers (LLVM 17 added them): a child forked while another thread refills the sanitizer's
/// allocator waits on that lock forever, and a busy server forks thousands of times. There `auto`
/// stays in process; `process`, said explicitly, still forks.
inline void set_server_isolation() {
  if (!kAddressSanitizer) kernel::set_auto_isolation(kernel::Isolation::process);
}

}  // namespace flipper::cli
