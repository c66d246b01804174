#!/usr/bin/env bash
# The layer check must catch what it is for: in a scratch tree of two plugins, `b` including a
# header of `a` (by a relative path, or by name through a borrowed include directory) and `b`
# linking a library of `a` must each fail layers.sh, and the clean tree must pass; so must a layer
# declaring another's config key, a key spelled twice, a string read of a key, a kernel over its
# line cap, and naturalization decoding a scorer's saved state. The toolkit's config module is the
# kernel's, naturalization's and the apps' only: they may include it, the SDK, the plugins and the
# plugins' toolkit may not; its process module is the kernel's only.
# Usage: layers_detect.sh <doc>
set -euo pipefail
doc=$1
check=$(dirname "${BASH_SOURCE[0]}")/layers.sh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

clean() {
  rm -rf "$tmp/tree"
  mkdir -p "$tmp/tree/plugins/a" "$tmp/tree/plugins/b" "$tmp/tree/sdk" "$tmp/tree/toolkit" \
    "$tmp/tree/language" "$tmp/tree/kernel" "$tmp/tree/naturalization" "$tmp/tree/apps"
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
clean
echo '#include "flipper/toolkit/params.hpp"  // not flipper/toolkit/config/' >"$tmp/tree/kernel/k.cpp"
expect fail "the kernel includes a toolkit header, naming the config module in a comment"
clean
echo '#include "flipper/toolkit/config_helpers.hpp"' >"$tmp/tree/apps/a.cpp"
expect fail "an app includes a toolkit header whose name starts with config"
clean
echo '#include "flipper/toolkit/config/document.hpp"' >"$tmp/tree/kernel/k.cpp"
echo '#include <flipper/toolkit/config/yaml_bounds.hpp>' >"$tmp/tree/naturalization/n.cpp"
echo '#include "flipper/toolkit/config/regular_file.hpp"' >"$tmp/tree/apps/a.cpp"
expect pass "the kernel, naturalization and an app include the toolkit's config module"
clean
echo '#include "flipper/toolkit/config/document.hpp"' >"$tmp/tree/sdk/s.cpp"
expect fail "the SDK includes the toolkit's config module"
clean
echo '#include "flipper/toolkit/config/document.hpp"' >>"$tmp/tree/plugins/b/b.cpp"
expect fail "a plugin includes the toolkit's config module"
clean
mkdir -p "$tmp/tree/toolkit/src"
echo '#include "flipper/toolkit/config/document.hpp"' >"$tmp/tree/toolkit/src/t.cpp"
expect fail "the plugins' toolkit includes its config module"
clean
printf 'flipper_add_plugin(b KIND world SOURCES b.cpp LIBRARIES flipper_toolkit_config)\n' \
  >"$tmp/tree/plugins/b/CMakeLists.txt"
expect fail "a plugin links the toolkit's config module"
# Each part declares its own config keys and reads them through handles (docs/config.md).
clean
printf 'inline constexpr Int kPort{"serve.port", 8410, 0, 65535, "port"};\n' >"$tmp/tree/kernel/keys.hpp"
expect fail "the kernel declares a studio key"
clean
mkdir -p "$tmp/tree/apps/studio"
printf 'inline constexpr Path kPath{\n    "lexicon.path", "", "store"};\n' \
  >"$tmp/tree/apps/studio/keys.hpp"
expect fail "the studio declares a naturalization key"
clean
mkdir -p "$tmp/tree/apps/cli"
printf 'auto a = Path{"lexicon.path"};\n' >"$tmp/tree/naturalization/keys.hpp"
printf 'bool b = x == "lexicon.path";  // "lexicon.path" in a comment is no spelling\n' \
  >"$tmp/tree/apps/cli/b.cpp"
expect fail "a key spelled in two places"
clean
printf 'auto a = Path{"lexicon.path"};  // "lexicon.path"\n' >"$tmp/tree/naturalization/keys.hpp"
expect pass "a key spelled once, and again in a comment"
clean
printf 'int k = config.get_int("session.k");\n' >"$tmp/tree/kernel/k.cpp"
expect fail "a string read of a config key"
clean
printf 'auto s = params.get_string(\n    "shape");\n' >"$tmp/tree/plugins/b/b.cpp"
expect fail "a string read of a plugin param over two lines"
clean
printf 'for (const auto& [p, m] : j.at("models").items()) {}\n' >"$tmp/tree/naturalization/n.cpp"
expect fail "naturalization decodes a scorer's saved state"
clean
printf 'out.push_back({p, "#accepts", c - 1, 0});\n' >"$tmp/tree/naturalization/n.cpp"
expect fail "naturalization spells the linear model's reserved weight"
clean
for i in $(seq 4001); do echo "int x$i;"; done >"$tmp/tree/kernel/big.cpp"
expect fail "a kernel of 4,001 lines"
clean
for i in $(seq 4000); do echo "int x$i;"; done >"$tmp/tree/kernel/big.cpp"
expect pass "a kernel of 4,000 lines"
clean
echo '#include "flipper/kernel/plugin_ref.hpp"' >"$tmp/tree/language/l.cpp"
expect fail "the core language includes a kernel header"
clean
echo '#include <flipper/toolkit/json/json_writer.hpp>' >"$tmp/tree/language/l.cpp"
expect fail "the core language includes a toolkit header"
clean
echo '#include "flipper/language/executor.hpp"' >"$tmp/tree/plugins/b/b.cpp"
expect fail "a plugin includes the core language's header"
clean
echo '#include "flipper/toolkit/json/json_writer.hpp"' >"$tmp/tree/plugins/b/b.cpp"
expect fail "a plugin includes the toolkit's JSON module"
clean
printf 'inline constexpr Int kK{"session.k", 3, 1, 9, "k"};\n' >"$tmp/tree/language/keys.hpp"
expect fail "the core language declares a kernel key"
clean
echo '#include "flipper/language/executor.hpp"' >"$tmp/tree/kernel/k.cpp"
echo '#include "flipper/toolkit/json/raw_members.hpp"' >"$tmp/tree/naturalization/n.cpp"
printf '#include "flipper/sdk/plugin.hpp"\n#include "flipper/language/keys.hpp"\n' >"$tmp/tree/language/l.cpp"
expect pass "the kernel includes the core language, naturalization the toolkit's JSON module"
clean
echo '#include "flipper/toolkit/process/child_call.hpp"' >"$tmp/tree/kernel/k.cpp"
expect pass "the kernel includes the toolkit's process module"
clean
echo '#include "flipper/toolkit/process/child_call.hpp"' >"$tmp/tree/naturalization/n.cpp"
expect fail "naturalization includes the toolkit's process module"
clean
echo '#include "flipper/toolkit/process/child_call.hpp"' >"$tmp/tree/plugins/b/b.cpp"
expect fail "a plugin includes the toolkit's process module"
clean
mkdir -p "$tmp/tree/toolkit/src"
echo '#include "flipper/toolkit/process/child_call.hpp"' >"$tmp/tree/toolkit/src/t.cpp"
expect fail "the plugins' toolkit includes its process module"
echo "layer check detection OK"
