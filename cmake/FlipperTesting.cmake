# flipper_add_conformance_test(<plugin> [LOADER_ONLY] [PARAMS <name=value>...] [WORLD <file>]
#                              [SOURCES <src>...] [LIBRARIES <lib>...])
#
# Builds the test executable conformance_<plugin> for the plugin built by
# flipper_add_plugin(<plugin> KIND <kind> ...) and registers each of its Catch2 test cases with
# CTest (needs Catch2 v2; call enable_testing() in the top CMakeLists.txt so that `ctest` finds
# them). It runs, on the built library, opened exactly as the kernel opens it:
# - the loader-layer kit (flipper/testing/loader.hpp): descriptor, handshake, schema, unknown-key
#   rejection, 100 create/destroy cycles;
# - unless LOADER_ONLY, the behaviour kit of the plugin's kind (flipper/testing/<kind>_
#   conformance.hpp) with the inputs of the driver flipper_<kind>_conformance.cpp: seeded mazes
#   (planner); a small world in the protocol's common format, or WORLD <file> (world); the core
#   grammar and core-language utterances, scored by the core bonus alone (parser); the toolkit's
#   chart parser over the core grammar (scorer); a few bodies on a small world (rewriter); word
#   samples (similarity).
# PARAMS gives parameter values (as `--set <section>.params.name=value` would: typed by the
# schema) to both, e.g. for a parameter without default. SOURCES adds tests of your own (they may
# call testing::load_plugin<Interface>("<plugin>"), flipper/testing/plugin_factory.hpp).
# Works in tree and out of tree (after find_package(FlipperSDK)).
include_guard(GLOBAL)

function(flipper_add_conformance_test plugin)
  cmake_parse_arguments(FACT "LOADER_ONLY" "WORLD" "PARAMS;SOURCES;LIBRARIES" ${ARGN})
  # The drivers lie beside this file (installed or in the source tree's cmake/), and so does the
  # core grammar the parser and scorer kits parse with, once installed (in the source tree the
  # top CMakeLists.txt points FLIPPER_CONFORMANCE_GRAMMAR at configs/grammars).
  set(kit_dir ${CMAKE_CURRENT_FUNCTION_LIST_DIR})
  set(grammar ${kit_dir}/core.grammar)
  if(DEFINED FLIPPER_CONFORMANCE_GRAMMAR)
    set(grammar ${FLIPPER_CONFORMANCE_GRAMMAR})
  endif()
  if(DEFINED FLIPPER_BUILD_TESTS AND NOT FLIPPER_BUILD_TESTS)
    return()
  endif()
  set(target flipper_plugin_${plugin})
  if(NOT TARGET ${target})
    message(FATAL_ERROR "flipper_add_conformance_test(${plugin}): no target ${target}; "
                        "call flipper_add_plugin(${plugin} ...) first")
  endif()
  get_target_property(kind ${target} FLIPPER_PLUGIN_KIND)
  get_target_property(plugin_dir ${target} FLIPPER_PLUGIN_OUTPUT_DIRECTORY)
  find_package(Catch2 2 REQUIRED)
  include(Catch)
  enable_testing()  # in the directory calling this; a top-level enable_testing() is still needed
  set(test conformance_${plugin})
  # The drivers in one translation unit (Catch2's header is parsed once).
  set(drivers "#include \"flipper_loader_conformance.cpp\"\n")
  if(NOT FACT_LOADER_ONLY)
    string(APPEND drivers "#include \"flipper_${kind}_conformance.cpp\"\n")
  endif()
  set(driver ${CMAKE_CURRENT_BINARY_DIR}/${test}_drivers.cpp)
  file(CONFIGURE OUTPUT ${driver} CONTENT "${drivers}")
  add_executable(${test} ${driver} ${FACT_SOURCES})
  if(TARGET flipper_sdk)
    target_link_libraries(${test} PRIVATE flipper_sdk flipper_toolkit)
    set_target_properties(${test} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  else()
    target_link_libraries(${test} PRIVATE Flipper::sdk Flipper::toolkit)
  endif()
  target_link_libraries(${test} PRIVATE Catch2::Catch2WithMain ${FACT_LIBRARIES})
  # The settings as one string literal, one per line.
  list(JOIN FACT_PARAMS "\\n" params)
  set(world "")
  if(FACT_WORLD)
    get_filename_component(world ${FACT_WORLD} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
  target_compile_definitions(${test} PRIVATE
    FLIPPER_CONFORMANCE_PLUGIN="${plugin}"
    FLIPPER_CONFORMANCE_PLUGIN_PATH="$<TARGET_FILE:${target}>"
    FLIPPER_PLUGIN_DIR="${plugin_dir}"
    FLIPPER_CONFORMANCE_PARAMS="${params}"
    FLIPPER_CONFORMANCE_WORLD="${world}"
    FLIPPER_CONFORMANCE_GRAMMAR="${grammar}")
  target_include_directories(${test} PRIVATE ${kit_dir})
  # In the source tree the drivers compile at the test units' level (FLIPPER_TEST_OPT, -O0 by
  # default; docs/testing.md "CI time"): they are Catch2 around calls into the plugin, which keeps
  # its own level, and each kit runs in milliseconds. Out of tree the build type decides.
  if(FLIPPER_TEST_OPT)
    target_compile_options(${test} PRIVATE ${FLIPPER_TEST_OPT})
  endif()
  set_target_properties(${test} PROPERTIES CXX_STANDARD 20 CXX_STANDARD_REQUIRED ON)
  add_dependencies(${test} ${target})
  catch_discover_tests(${test} TEST_PREFIX "${test}." PROPERTIES TIMEOUT 300)
endfunction()
