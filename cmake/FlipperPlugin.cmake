# flipper_add_plugin(<name> KIND <kind> SOURCES <src>... [LIBRARIES <lib>...] [VERSION <v>]
#                    [DIMS <2|3>] [OUTPUT_DIRECTORY <dir>] [NAME <id>] [NO_INSTALL])
#
# Builds a Flipper plugin: a MODULE library linked against the SDK and the toolkit only (the
# toolkit is a static library: a plugin takes from it only what it uses), with hidden visibility,
# -fno-gnu-unique (so g++ does not pin it in memory, see docs) and -z nodelete (the kernel never
# unloads within a process), written to the plugin directory together with a sidecar manifest
# <name>.flipper.yaml that lets the kernel index plugins without loading their code.
# Works in tree (target flipper_sdk) and out of tree (after find_package(FlipperSDK)).
# NAME overrides the plugin id written to the sidecar (default: <name>; tests use it to build
# two files declaring one id). DIMS (world plugins) writes the dimensions of the worlds the plugin
# reads into the sidecar: the kernel names the plugins for a world of the other dimensions from
# it without loading their code (docs/worlds.md). Unless NO_INSTALL, `cmake --install` puts the plugin and its
# sidecar in <prefix>/lib/flipper/plugins, where an installed kernel looks.
include_guard(GLOBAL)
include(GNUInstallDirs)
set(FLIPPER_PLUGIN_INSTALL_DIR "lib/flipper/plugins" CACHE STRING
  "Plugin install directory, relative to the prefix (the kernel searches <exe>/../lib/flipper/plugins)")

function(flipper_add_plugin name)
  cmake_parse_arguments(FAP "NO_INSTALL" "KIND;VERSION;DIMS;OUTPUT_DIRECTORY;NAME" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT FAP_KIND)
    message(FATAL_ERROR "flipper_add_plugin(${name}): KIND is required")
  endif()
  set(kinds world planner parser scorer rewriter similarity frontend)
  if(NOT FAP_KIND IN_LIST kinds)
    message(FATAL_ERROR "flipper_add_plugin(${name}): KIND ${FAP_KIND} is not one of ${kinds}")
  endif()
  set(dims_line "")
  if(FAP_DIMS)
    if(NOT FAP_KIND STREQUAL "world" OR NOT FAP_DIMS MATCHES "^[23]$")
      message(FATAL_ERROR "flipper_add_plugin(${name}): DIMS is 2 or 3, for world plugins only")
    endif()
    set(dims_line "dims: ${FAP_DIMS}\n")
  endif()
  if(NOT FAP_SOURCES)
    message(FATAL_ERROR "flipper_add_plugin(${name}): SOURCES is required")
  endif()
  if(NOT FAP_NAME)
    set(FAP_NAME ${name})
  endif()
  if(NOT FAP_VERSION)
    set(FAP_VERSION "1.0.0")
  endif()
  if(NOT FAP_OUTPUT_DIRECTORY)
    if(DEFINED FLIPPER_PLUGIN_OUTPUT_DIR)
      set(FAP_OUTPUT_DIRECTORY ${FLIPPER_PLUGIN_OUTPUT_DIR})
    else()
      set(FAP_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/plugins)
    endif()
  endif()
  # Developer aid for a shared work tree: skip (with a warning) a plugin whose sources are not
  # all written yet instead of failing the whole configure. Off by default, so CI stays strict.
  if(FLIPPER_SKIP_INCOMPLETE_PLUGINS)
    foreach(src ${FAP_SOURCES})
      if(NOT IS_ABSOLUTE ${src})
        set(src ${CMAKE_CURRENT_SOURCE_DIR}/${src})
      endif()
      if(NOT EXISTS ${src})
        message(WARNING "flipper_add_plugin(${name}): skipped, missing source ${src}")
        return()
      endif()
    endforeach()
  endif()
  set(target flipper_plugin_${name})
  add_library(${target} MODULE ${FAP_SOURCES})
  # Warnings of plugin code: in tree the project's strict set (FLIPPER_STRICT_WARNINGS, which
  # FLIPPER_WERROR makes errors), out of tree -Wall -Wextra.
  set(warnings -Wall -Wextra)
  if(DEFINED FLIPPER_STRICT_WARNINGS)
    set(warnings ${FLIPPER_STRICT_WARNINGS})
  endif()
  if(TARGET flipper_sdk)
    target_link_libraries(${target} PRIVATE flipper_sdk flipper_toolkit)
  else()
    target_link_libraries(${target} PRIVATE Flipper::sdk Flipper::toolkit)
  endif()
  if(FAP_LIBRARIES)
    target_link_libraries(${target} PRIVATE ${FAP_LIBRARIES})
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME ${name}
    LIBRARY_OUTPUT_DIRECTORY ${FAP_OUTPUT_DIRECTORY}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    POSITION_INDEPENDENT_CODE ON
    CXX_STANDARD 20
    CXX_STANDARD_REQUIRED ON
    FLIPPER_PLUGIN_KIND ${FAP_KIND}
    FLIPPER_PLUGIN_OUTPUT_DIRECTORY ${FAP_OUTPUT_DIRECTORY})
  # g++ only: clang never emits STB_GNU_UNIQUE symbols (and has no such flag).
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-gnu-unique>
    ${warnings})
  target_link_options(${target} PRIVATE -Wl,-z,nodelete)
  # The entry function is the plugin's only exported symbol: template instantiations of std::
  # (default visibility despite -fvisibility=hidden) stay local, so two plugins never bind to
  # each other's copies and the dynamic symbol table stays small.
  set(version_script ${CMAKE_BINARY_DIR}/flipper_plugin.map)
  if(NOT EXISTS ${version_script})
    file(WRITE ${version_script} "{ global: flipper_plugin_entry; local: *; };\n")
  endif()
  target_link_options(${target} PRIVATE -Wl,--version-script=${version_script})
  set_property(TARGET ${target} APPEND PROPERTY LINK_DEPENDS ${version_script})
  # One source for the version: the sidecar and the descriptor (FLIPPER_PLUGIN(..., version, ...)
  # with FLIPPER_PLUGIN_VERSION) both take VERSION.
  target_compile_definitions(${target} PRIVATE FLIPPER_PLUGIN_VERSION="${FAP_VERSION}")
  if(NOT FLIPPER_PLUGIN_ALLOW_UNDEFINED)  # sanitizer builds: see FlipperSanitize.cmake
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
  file(GENERATE OUTPUT ${FAP_OUTPUT_DIRECTORY}/${name}.flipper.yaml CONTENT
"name: ${FAP_NAME}
kind: ${FAP_KIND}
version: ${FAP_VERSION}
library: ${name}.so
${dims_line}")
  if(NOT FAP_NO_INSTALL)
    # Installed plugins find libflipper_sdk in <prefix>/<libdir> (3 levels up from the plugin).
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/../../../${CMAKE_INSTALL_LIBDIR}")
    install(TARGETS ${target} LIBRARY DESTINATION ${FLIPPER_PLUGIN_INSTALL_DIR})
    install(FILES ${FAP_OUTPUT_DIRECTORY}/${name}.flipper.yaml DESTINATION ${FLIPPER_PLUGIN_INSTALL_DIR})
  endif()
endfunction()

include(${CMAKE_CURRENT_LIST_DIR}/FlipperTesting.cmake)
