# Writes the source commit into a generated C++ file at build time (not configure time), so a
# rebuild after a commit or an edit records the tree it was built from (docs/experiments.md §2).
# Run as `cmake -DSOURCE_DIR=... -DOUTPUT=... -P FlipperBuildInfo.cmake` by the flipper_build_info
# target. Without git, or when the source tree is not the top of a git checkout, the commit is
# "unknown" and the build goes on.
# The file is rewritten only when its text changes, so an unchanged tree recompiles nothing.
set(commit "unknown")
set(describe "unknown")
set(dirty "unknown")
find_program(GIT_EXECUTABLE git)
if(GIT_EXECUTABLE)
  # Only the source tree's own repository counts: an unpacked archive that happens to lie inside
  # another checkout must not take that checkout's commit.
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} rev-parse --show-toplevel
    OUTPUT_VARIABLE top RESULT_VARIABLE rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  get_filename_component(source_real "${SOURCE_DIR}" REALPATH)
  if(rc EQUAL 0 AND top)
    get_filename_component(top "${top}" REALPATH)
  endif()
  set(out "")
  if(rc EQUAL 0 AND top STREQUAL source_real)
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} rev-parse HEAD
      OUTPUT_VARIABLE out RESULT_VARIABLE rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
  endif()
  if(rc EQUAL 0 AND out)
    set(commit "${out}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} describe --always --dirty
      OUTPUT_VARIABLE out RESULT_VARIABLE rc ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(rc EQUAL 0 AND out)
      set(describe "${out}")
      if(describe MATCHES "-dirty$")
        set(dirty "yes")
      else()
        set(dirty "no")
      endif()
    endif()
  endif()
endif()
set(text "// Generated at build time by cmake/FlipperBuildInfo.cmake: do not edit.
namespace flipper::record::generated {
extern const char* const kCommit;
extern const char* const kDescribe;
extern const char* const kDirty;
const char* const kCommit = \"${commit}\";
const char* const kDescribe = \"${describe}\";
const char* const kDirty = \"${dirty}\";
}  // namespace flipper::record::generated
")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
