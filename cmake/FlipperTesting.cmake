# flipper_add_conformance_test(<plugin> [SOURCES <src>...] [LIBRARIES <lib>...])
#
# Builds test executable conformance_<plugin>: the loader-layer conformance kit
# (flipper/testing/loader.hpp) run on the built library of flipper_plugin_<plugin>, whose path
# CMake injects, plus any SOURCES (e.g. a FLIPPER_PLANNER_CONFORMANCE(...) behaviour kit). Each
# Catch2 test case becomes a CTest test. Works in tree and out of tree (after
# find_package(FlipperSDK)); needs Catch2 v2.
include_guard(GLOBAL)
set(FLIPPER_TESTING_CMAKE_DIR ${CMAKE_CURRENT_LIST_DIR})

function(flipper_add_conformance_test plugin)
  cmake_parse_arguments(FACT "" "" "SOURCES;LIBRARIES" ${ARGN})
  if(DEFINED FLIPPER_BUILD_TESTS AND NOT FLIPPER_BUILD_TESTS)
    return()
  endif()
  if(NOT TARGET flipper_plugin_${plugin})
    message(FATAL_ERROR "flipper_add_conformance_test(${plugin}): no target flipper_plugin_${plugin}; "
                        "call flipper_add_plugin(${plugin} ...) first")
  endif()
  find_package(Catch2 2 REQUIRED)
  include(Catch)
  enable_testing()
  set(test conformance_${plugin})
  add_executable(${test} ${FLIPPER_TESTING_CMAKE_DIR}/flipper_loader_conformance.cpp ${FACT_SOURCES})
  if(TARGET flipper_sdk)
    target_link_libraries(${test} PRIVATE flipper_sdk)
    set_target_properties(${test} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  else()
    target_link_libraries(${test} PRIVATE Flipper::sdk)
  endif()
  target_link_libraries(${test} PRIVATE Catch2::Catch2WithMain ${FACT_LIBRARIES})
  target_compile_definitions(${test} PRIVATE
    FLIPPER_CONFORMANCE_PLUGIN="${plugin}"
    FLIPPER_CONFORMANCE_PLUGIN_PATH="$<TARGET_FILE:flipper_plugin_${plugin}>")
  set_target_properties(${test} PROPERTIES CXX_STANDARD 20 CXX_STANDARD_REQUIRED ON)
  add_dependencies(${test} flipper_plugin_${plugin})
  catch_discover_tests(${test} TEST_PREFIX "${test}." PROPERTIES TIMEOUT 300)
endfunction()
