#!/usr/bin/env bash
# Out-of-tree plugins against an installed SDK, as a plugin author works (docs/plugins.md):
# 1. install the SDK (component "sdk") into a temp prefix: headers, libflipper_sdk, the toolkit,
#    the CMake package with the conformance kits, the example under share/flipper/examples;
# 2. docs/plugins.md's CMake snippet is the installed example's CMakeLists.txt, byte for byte;
# 3. build a copy of the installed example against that prefix alone, run its ctest (loader kit,
#    planner kit, its own test) and load it with build/bin/flipper;
# 4. the build fingerprint names the standard library's ABI, not the compiler: the example built
#    with clang++-14 (against the same libstdc++) is accepted and loads into the g++-built
#    flipper; libstdc++'s old string ABI is refused at configure time, naming both fingerprints;
# 5. scaffold one plugin of each kind with `flipper plugin new`, build the six in one CMake project
#    (warnings are errors), run their kits and tests, list them and run a query with all six.
# Usage: out_of_tree.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
flipper=$build/bin/flipper
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
start=$SECONDS
step() { echo "== $* (at $((SECONDS - start)) s)"; }
fail() {
  echo "FAILED: $*"
  exit 1
}
kinds="world planner parser scorer rewriter similarity"

step "1. install the SDK component"
prefix=$tmp/prefix
cmake --install "$build" --component sdk --prefix "$prefix" >/dev/null
example=$prefix/share/flipper/examples/out-of-tree-planner
for f in lib/libflipper_toolkit.a lib/cmake/FlipperSDK/core.grammar \
  include/flipper/toolkit/params.hpp include/flipper/testing/plugin_factory.hpp \
  "share/flipper/examples/out-of-tree-planner/CMakeLists.txt"; do
  test -f "$prefix/$f" || fail "the SDK install lacks $f"
done

step "2. docs/plugins.md's CMake snippet is the installed example's CMakeLists.txt"
awk '/<!-- readme-cmake: examples\/out-of-tree-planner\/CMakeLists.txt/ {marked = 1; next}
     marked && /^```/ {if (inside) exit; inside = 1; next}
     inside {print}' "$src/docs/plugins.md" >"$tmp/readme-snippet.cmake"
test -s "$tmp/readme-snippet.cmake" || fail "no marked CMake snippet in docs/plugins.md"
diff -u "$tmp/readme-snippet.cmake" "$example/CMakeLists.txt" ||
  fail "docs/plugins.md's snippet differs from examples/out-of-tree-planner/CMakeLists.txt"

step "3. build the installed example against the prefix alone, test it, load it"
cp -r "$example" "$tmp/example"
cmake -S "$tmp/example" -B "$tmp/example-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
cmake --build "$tmp/example-build" -j2
ctest --test-dir "$tmp/example-build" --output-on-failure --no-tests=error
ctest --test-dir "$tmp/example-build" -N | grep -q "Total Tests: 3$" ||
  fail "the example should have 3 tests (loader kit, planner kit, its own)"
plugins=$tmp/example-build/plugins
test -f "$plugins/bfs_example.so" && test -f "$plugins/bfs_example.flipper.yaml"
# The listing marks bfs_example as selected and loadable (other rows may vary with the build).
listing=$("$flipper" plugins --set "plugin_paths=[$plugins]" --set planner.plugin=bfs_example || true)
echo "$listing"
echo "$listing" | grep -Eq "^\* bfs_example +planner +0\.1\.0 +3 \(sdk 3\.[0-9]+\) +$plugins/bfs_example\.so +ok$"
# A full check instantiates it with the kernel test plugins, and with the default config.
"$flipper" config check --config "$src/tests/kernel/data/kernel_test.yaml" \
  --set "plugin_paths=[$plugins, $build/tests/plugins/good]" --set planner.plugin=bfs_example \
  --set planner.params=null |
  grep -q "plugin: bfs_example"
"$flipper" config check --set "plugin_paths=[$plugins]" --set planner.plugin=bfs_example |
  grep -q "plugin: bfs_example"

step "4. another compiler is accepted, another string ABI refused at configure time"
refused() {  # refused <what> <expected fingerprint part> <cmake args...>
  local what=$1 part=$2
  shift 2
  if cmake -S "$tmp/example" -B "$tmp/refused" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "$@" >"$tmp/refused.log" 2>&1; then
    cat "$tmp/refused.log"
    fail "configuring with $what succeeded"
  fi
  # CMake wraps the package's message: compare it as one line.
  tr -s '\n ' '  ' <"$tmp/refused.log" >"$tmp/refused.line"
  grep -q "does not match the Flipper SDK" "$tmp/refused.line" &&
    grep -qF "fingerprint $sdk_fingerprint" "$tmp/refused.line" &&
    grep -q "this project: .*fingerprint $part" "$tmp/refused.line" ||
    {
      cat "$tmp/refused.log"
      fail "configuring with $what did not report the fingerprint mismatch"
    }
  echo "refused: $what"
  grep -o "this project: .*fingerprint [^ ]*" "$tmp/refused.line"
  rm -rf "$tmp/refused"
}
sdk_fingerprint=$(sed -n 's/^set(FlipperSDK_BUILD_FINGERPRINT "\(.*\)")$/\1/p' \
  "$prefix/lib/cmake/FlipperSDK/FlipperSDKConfig.cmake")
echo "the SDK's build fingerprint: $sdk_fingerprint"
abi=$(sed -n 's/^#define FLIPPER_PLUGIN_ABI \([0-9]*\)$/\1/p' "$src/sdk/include/flipper/sdk/version.hpp")
[[ $sdk_fingerprint == "abi=$abi;libstdc++;cxx11abi=1;ptrsize=8" ]] ||
  fail "unexpected SDK fingerprint (want abi=$abi;libstdc++;cxx11abi=1;ptrsize=8)"
command -v clang++-14 >/dev/null || fail "clang++-14 is needed (scripts/packages.txt)"
# clang++ against libstdc++ has the same fingerprint: its plugin loads into the g++ kernel.
cmake -S "$tmp/example" -B "$tmp/clang" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
cmake --build "$tmp/clang" -j2 --target flipper_plugin_bfs_example
grep -q "clang" "$tmp/clang/CMakeCache.txt" || fail "the clang build did not use clang++"
cplugins=$tmp/clang/plugins
listing=$("$flipper" plugins --set "plugin_paths=[$cplugins]" --set planner.plugin=bfs_example || true)
echo "$listing" | grep -Eq "^\* bfs_example +planner +0\.1\.0 +3 \(sdk 3\.[0-9]+\) +$cplugins/bfs_example\.so +ok$" ||
  fail "the example built with clang++-14 does not load: $listing"
echo '{"bounds": {"min": [0, 0], "max": [4, 4]}, "robot": {"x": 1, "y": 1}}' >"$tmp/clang-field.json"
out=$("$flipper" run --json --set "plugin_paths=[$cplugins]" --set planner.plugin=bfs_example \
  --set planner.params=null --set lexicon.path=:memory: --set "world.file=$tmp/clang-field.json" \
  "visit [3,1]")
echo "$out" | grep -qF '"robot":{"holding":[],"x":3,"y":1}' ||
  fail "the clang-built planner did not take the robot to [3,1]: $out"
echo "accepted: clang++-14 (fingerprint $sdk_fingerprint), and its plugin planned"
refused "-D_GLIBCXX_USE_CXX11_ABI=0" "abi=$abi;libstdc++;cxx11abi=0;" \
  -DCMAKE_CXX_FLAGS=-D_GLIBCXX_USE_CXX11_ABI=0

step "5. scaffold one plugin of each kind, build, test and load the six"
scaffolds=$tmp/scaffolds
mkdir -p "$scaffolds"
{
  echo "cmake_minimum_required(VERSION 3.22)"
  echo "project(scaffolds LANGUAGES CXX)"
  echo "enable_testing()"
} >"$scaffolds/CMakeLists.txt"
for kind in $kinds; do
  "$flipper" plugin new "$kind" "my_$kind" "$scaffolds/my_$kind"
  echo "add_subdirectory(my_$kind)" >>"$scaffolds/CMakeLists.txt"
done
# A second scaffold into a non-empty folder is refused (exit 2), and so is a bad name.
if "$flipper" plugin new world my_world "$scaffolds/my_world" 2>"$tmp/err"; then
  fail "plugin new wrote into a non-empty folder"
fi
grep -q "exists and is not empty" "$tmp/err"
set +e
"$flipper" plugin new planner 2fast "$tmp/x" 2>"$tmp/err"
status=$?
set -e
[[ $status == 2 ]] && grep -q "is not a plugin name" "$tmp/err" || fail "a bad name was not refused"
cmake -S "$scaffolds" -B "$scaffolds/build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "-DCMAKE_CXX_FLAGS=-Wall -Wextra -Wshadow -Werror" \
  >/dev/null
cmake --build "$scaffolds/build" -j2
ctest --test-dir "$scaffolds/build" --output-on-failure --no-tests=error -j2
for kind in $kinds; do  # each: the loader kit, its kind's kit, its own test
  n=$(ctest --test-dir "$scaffolds/build" -N -R "^conformance_my_$kind\." | grep -c "Test *#" || true)
  [[ $n == 3 ]] || fail "my_$kind has $n tests, not 3"
done
sp=$scaffolds/build/plugins
listing=$("$flipper" plugins --set "plugin_paths=[$sp]")
echo "$listing"
for kind in $kinds; do
  echo "$listing" | grep -Eq "^  my_$kind +$kind +0\.1\.0 +3 \(sdk 3\.[0-9]+\) +$sp/my_$kind\.so +ok$" ||
    fail "my_$kind is not listed as a loadable $kind plugin"
done
# All six at once, in one runtime: a query parsed, scored, planned on the scaffolded world.
echo '{"bounds": {"min": [0, 0], "max": [4, 4]}, "robot": {"x": 1, "y": 1}}' >"$tmp/field.json"
sets=(--set "plugin_paths=[$sp]" --set lexicon.path=:memory: --set "world.file=$tmp/field.json")
for kind in $kinds; do sets+=(--set "$kind.plugin=my_$kind" --set "$kind.params=null"); done
"$flipper" config check "${sets[@]}" >/dev/null
out=$("$flipper" run --json "${sets[@]}" "Move UP")
echo "$out"
echo "$out" | grep -qF '"formula":"{move up}"' && echo "$out" | grep -qF '"to":[1,2]' &&
  echo "$out" | grep -qF '"robot":{"holding":[],"x":1,"y":2}' ||
  fail "the query did not move the robot from (1,1) up to (1,2)"
step "out-of-tree plugins OK"
