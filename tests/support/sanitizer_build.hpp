#pragma once
// Whether this test is compiled with AddressSanitizer (the build-fuzz/ tree, scripts/test's second
// part). Instrumented processes are several times slower and their resident memory carries ASan's
// shadow and redzones, so timing margins widen and resident-size bounds are checked in the Release
// run only.
namespace flipper::testsupport {
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif
}  // namespace flipper::testsupport
