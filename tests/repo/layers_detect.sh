#!/usr/bin/env bash
# The layer check must catch what it is for: in a scratch tree of two plugins, `b` including a
# header of `a` (by a relative path, or by name through a borrowed include directory) and `b`
# linking a library of `a` must each fail layers.sh, and the clean tree must pass.
# Usage: layers_detect.sh <doc>
set -euo pipefail
doc=$1
check=$(dirname "${BASH_SOURCE[0]}")/layers.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

clean() {
  rm -rf "$tmp/tree"
  mkdir -p "$tmp/tree/plugins/a" "$tmp/tree/plugins/b" "$tmp/tree/sdk" "$tmp/tree/toolkit" \
    "$tmp/tree/kernel" "$tmp/tree/naturalization" "$tmp/tree/apps"
  printf '#pragma once\nint a_helper();\n' >"$tmp/tree/plugins/a/helper.hpp"
  printf '#include "helper.hpp"\n#include "flipper/sdk/plugin.hpp"\n' >"$tmp/tree/plugins/a/a.cpp"
  printf '#include "flipper/toolkit/params.hpp"\n' >"$tmp/tree/plugins/b/b.cpp"
  printf 'flipper_add_plugin(a KIND world SOURCES a.cpp)\n' >"$tmp/tree/plugins/a/CMakeLists.txt"
  printf 'flipper_add_plugin(b KIND world SOURCES b.cpp LIBRARIES flipper_toolkit)\n' \
    >"$tmp/tree/plugins/b/CMakeLists.txt"
}
expect() {  # expect pass|fail <what>
  if bash "$check" "$doc" "$tmp/tree" >"$tmp/out" 2>&1; then result=pass; else result=fail; fi
  if [[ $result != "$1" ]]; then
    echo "expected the layer check to $1 for: $2"
    cat "$tmp/out"
    exit 1
  fi
  echo "$1 as expected: $2"
}

clean
expect pass "two plugins, each on the SDK and the toolkit"
clean
echo '#include "../a/helper.hpp"' >>"$tmp/tree/plugins/b/b.cpp"
expect fail "b includes ../a/helper.hpp"
clean
echo '#include "helper.hpp"' >>"$tmp/tree/plugins/b/b.cpp"
echo 'target_include_directories(flipper_plugin_b PRIVATE ${CMAKE_SOURCE_DIR}/plugins/a)' \
  >>"$tmp/tree/plugins/b/CMakeLists.txt"
expect fail "b includes helper.hpp of a through a's folder"
clean
printf 'add_library(a_shared STATIC helper.cpp)\nflipper_add_plugin(a KIND world SOURCES a.cpp)\n' \
  >"$tmp/tree/plugins/a/CMakeLists.txt"
printf 'flipper_add_plugin(b KIND world SOURCES b.cpp LIBRARIES a_shared)\n' \
  >"$tmp/tree/plugins/b/CMakeLists.txt"
expect fail "a declares a library that b links"
clean
printf 'flipper_add_plugin(b KIND world SOURCES b.cpp LIBRARIES flipper_plugin_a)\n' \
  >"$tmp/tree/plugins/b/CMakeLists.txt"
expect fail "b links a's plugin target"
clean
echo '#include "flipper/kernel/config.hpp"' >>"$tmp/tree/plugins/b/b.cpp"
expect fail "b includes a kernel header"
clean
echo '#include <flipper/naturalization/induction.hpp>' >>"$tmp/tree/plugins/b/b.cpp"
expect fail "b includes a naturalization header with angle brackets"
clean
echo '#include "flipper/toolkit/params.hpp"' >"$tmp/tree/kernel/k.cpp"
expect fail "the kernel includes a toolkit header"
echo "layer check detection OK"
