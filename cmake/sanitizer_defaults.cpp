// The AddressSanitizer defaults of every executable of the instrumented tree (build-fuzz/,
// cmake/FlipperSanitize.cmake; docs/testing.md "Fuzzing and sanitizers"). ASAN_OPTIONS given at
// run time are read after these and win.
//
// intercept_tls_get_addr=0: clang 14's runtime records each dynamic TLS block (the thread_local
// variables of a dlopen()ed plugin) from its __tls_get_addr interceptor, and takes a block it did
// not see allocated whose address is 16 bytes past a page boundary for glibc 2.19's layout: it
// reads a "size" and a "start" from the 16 bytes before it. With glibc >= 2.34 those bytes are
// ASan's own chunk header, so the "start" is a stack-depot id (a small number), and the
// exit-time leak check scans from there: "Tracer caught signal 11: addr=0x…", "LeakSanitizer
// has encountered a fatal error", the process's buffered stdout lost. Which block lands there
// depends on every allocation before it (arguments, paths, environment), so a command crashed
// the same way on each run on one machine and never on another. Without the interceptor the
// runtime keeps no dynamic TLS ranges and the leak check does not scan them; the static TLS of
// the executable and the libraries it starts with is scanned as before.
extern "C" const char* __asan_default_options() {  // NOLINT: the runtime's hook has this name
  return "intercept_tls_get_addr=0";
}
