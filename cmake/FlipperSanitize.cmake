# Sanitizer and fuzzing builds (docs/testing.md "Fuzzing and sanitizers").
#
#   FLIPPER_SANITIZE=ON  ASan + UBSan (-fno-sanitize-recover=undefined) on every target: the SDK,
#                        the kernel, the plugins and the tests get the same flags, so the plugins
#                        the kernel dlopen()s run instrumented inside an instrumented process.
#   FLIPPER_FUZZ=ON      clang only; implies FLIPPER_SANITIZE and adds libFuzzer coverage
#                        (-fsanitize=fuzzer-no-link) everywhere, and builds the fuzz/ targets.
# Use a build dir of its own: CC=clang-14 CXX=clang++-14 cmake -B build-fuzz -DFLIPPER_FUZZ=ON
include_guard(GLOBAL)
option(FLIPPER_SANITIZE "Build everything with ASan + UBSan" OFF)
option(FLIPPER_FUZZ "Build the libFuzzer targets in fuzz/ (clang; implies FLIPPER_SANITIZE)" OFF)

if(FLIPPER_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "FLIPPER_FUZZ needs clang (libFuzzer): "
                        "CC=clang-14 CXX=clang++-14 cmake -B build-fuzz -DFLIPPER_FUZZ=ON")
  endif()
  set(FLIPPER_SANITIZE ON CACHE BOOL "Build everything with ASan + UBSan" FORCE)
endif()

# The instrumented tree compiles at FLIPPER_SANITIZE_OPT (default -O1, the level the ASan manual
# recommends) instead of the Release -O2: the same checks run, and the optimiser's most costly
# passes, which this tree is not for, are skipped. -DFLIPPER_SANITIZE_OPT=-O2 restores -O2.
set(FLIPPER_SANITIZE_OPT -O1 CACHE STRING "Optimisation level of the sanitizer build")
if(FLIPPER_SANITIZE)
  foreach(lang C CXX)
    set(CMAKE_${lang}_FLAGS_RELEASE "${FLIPPER_SANITIZE_OPT} -DNDEBUG")
  endforeach()
  set(flipper_sanitizers -fsanitize=address,undefined -fno-sanitize-recover=undefined)
  add_compile_options(${flipper_sanitizers} -fno-omit-frame-pointer -g1)
  add_link_options(${flipper_sanitizers})
  if(FLIPPER_FUZZ)
    add_compile_options(-fsanitize=fuzzer-no-link)
  endif()
  # Links with lld where clang finds it (Debian's lld-14, scripts/packages-test.txt): an
  # instrumented executable links 3-4x faster than with GNU ld (CPU, median of 2: a test 0.25 ->
  # 0.09 s, build/bin/flipper 1.5 -> 0.35 s). GNU ld where it is missing.
  include(CheckLinkerFlag)
  check_linker_flag(CXX -fuse-ld=lld FLIPPER_HAVE_LLD)
  if(FLIPPER_HAVE_LLD)
    add_link_options(-fuse-ld=lld)
  endif()
  # Every executable links the tree's ASan defaults (cmake/sanitizer_defaults.cpp says why each).
  add_library(flipper_sanitizer_defaults OBJECT ${CMAKE_CURRENT_LIST_DIR}/sanitizer_defaults.cpp)
  link_libraries("$<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:flipper_sanitizer_defaults>")
  # Shared objects do not carry the sanitizer runtime (the executable does), so with clang their
  # __asan_*/__ubsan_* references stay undefined until load: plugins drop -Wl,--no-undefined.
  set(FLIPPER_PLUGIN_ALLOW_UNDEFINED ON)
endif()

# The front ends (apps/ repl, planbench, studio, dds, cli: flipper_add_front_end in
# apps/CMakeLists.txt) compile in the instrumented tree without libFuzzer's coverage: no fuzz
# target links them (flipper_add_fuzzer refuses one that would), still under ASan + UBSan.
# FLIPPER_SANITIZE_FRONT_END_OPT (default -O0; empty: the tree's FLIPPER_SANITIZE_OPT) gives them a
# level of their own. At -O0 they compile about 3x faster: 301 -> 110 s of CPU for the five front
# ends (apps/studio's batch with the Beast/Asio HTTP transport alone 91 -> 29 s, most of it the
# optimiser and code generation of Beast's templates). The instrumented tests that run them take
# about 6 % more CPU (609 -> 646 s for the whole suite, likely the inline functions they
# instantiate, json's and std's, being the copies the linker keeps for the kernel code in the same
# binary too), so a cold CI spends about 2.6 CPU-minutes less, with the same sanitizers on the same
# code (docs/testing.md, "CI time"). -DFLIPPER_SANITIZE_FRONT_END_OPT= restores the tree's level.
set(FLIPPER_SANITIZE_FRONT_END_OPT -O0 CACHE STRING
  "Optimisation level of the front ends in the sanitizer build (empty: FLIPPER_SANITIZE_OPT)")

# flipper_drop_fuzz_coverage([OPTION...]): the current directory's targets, from here on, compile
# without libFuzzer's coverage (-fsanitize=fuzzer-no-link) and with OPTIONs after the others (the
# units under tests/, and the front ends through flipper_add_front_end).
function(flipper_drop_fuzz_coverage)
  get_directory_property(options COMPILE_OPTIONS)
  list(REMOVE_ITEM options -fsanitize=fuzzer-no-link)
  list(APPEND options ${ARGN})
  set_directory_properties(PROPERTIES COMPILE_OPTIONS "${options}")
endfunction()
