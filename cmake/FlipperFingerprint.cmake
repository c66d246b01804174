# flipper_detect_fingerprint(<out-var> <sdk include dir>)
#
# The build fingerprint (flipper/sdk/version.hpp: FLIPPER_BUILD_FINGERPRINT — the plugin ABI, the
# C++ standard library and its ABI, the pointer size; no compiler name) that this project's C++
# compiler, with its flags, would write into a plugin. The plugin loader refuses a plugin whose fingerprint
# differs from the kernel's; the FlipperSDK package compares it at configure time, so a mismatch
# is reported before anything is built. Compiles one file (a static library, nothing is run) and
# reads the string back from it; cached per compiler, flags and version.hpp.
include_guard(GLOBAL)

function(flipper_detect_fingerprint out sdk_include_dir)
  set(probe [=[
#include "flipper/sdk/plugin.hpp"  // as a plugin includes it
extern const char flipper_fingerprint[];
const char flipper_fingerprint[] = "FLIPPER_FINGERPRINT[" FLIPPER_BUILD_FINGERPRINT "]";
]=])
  # Cached per compiler, flags and version.hpp (which defines the fingerprint).
  file(MD5 ${sdk_include_dir}/flipper/sdk/version.hpp version_hash)
  string(MD5 key
    "${CMAKE_CXX_COMPILER}|${CMAKE_CXX_FLAGS}|${sdk_include_dir}|${version_hash}|${probe}")
  if(DEFINED FLIPPER_FINGERPRINT_KEY AND FLIPPER_FINGERPRINT_KEY STREQUAL key)
    set(${out} "${FLIPPER_FINGERPRINT_VALUE}" PARENT_SCOPE)
    return()
  endif()
  set(dir ${CMAKE_BINARY_DIR}/CMakeFiles/flipper_fingerprint)
  file(WRITE ${dir}/fingerprint.cpp "${probe}")
  set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
  try_compile(compiled ${dir}/build SOURCES ${dir}/fingerprint.cpp
    CMAKE_FLAGS "-DINCLUDE_DIRECTORIES=${sdk_include_dir}"
    LINK_LIBRARIES Boost::headers
    CXX_STANDARD 20 CXX_STANDARD_REQUIRED ON
    OUTPUT_VARIABLE log
    COPY_FILE ${dir}/fingerprint.bin)
  if(NOT compiled)
    message(FATAL_ERROR "Flipper: could not compile the build fingerprint probe "
                        "(${dir}/fingerprint.cpp) with ${CMAKE_CXX_COMPILER}:\n${log}")
  endif()
  file(STRINGS ${dir}/fingerprint.bin found REGEX "FLIPPER_FINGERPRINT\\[[^]]*\\]")
  string(REGEX REPLACE ".*FLIPPER_FINGERPRINT\\[([^]]*)\\].*" "\\1" value "${found}")
  string(REPLACE "\\;" ";" value "${value}")  # file(STRINGS) escapes the ';' of its list items
  set(FLIPPER_FINGERPRINT_KEY "${key}" CACHE INTERNAL "compiler and flags of the fingerprint")
  set(FLIPPER_FINGERPRINT_VALUE "${value}" CACHE INTERNAL "the build fingerprint of the compiler")
  set(${out} "${value}" PARENT_SCOPE)
endfunction()
