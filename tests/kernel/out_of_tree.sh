#!/usr/bin/env bash
# Out-of-tree plugin check: install the SDK (component "sdk") into a temp prefix, build
# examples/out-of-tree-planner against that prefix alone, run its conformance test, then load
# the plugin with the in-tree kernel (`flipper plugins` and `flipper config check`).
# Usage: out_of_tree.sh <source dir> <build dir>
set -euo pipefail
src=$1
build=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake --install "$build" --component sdk --prefix "$tmp/prefix" >/dev/null
cmake -S "$src/examples/out-of-tree-planner" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
cmake --build "$tmp/build" -j2
ctest --test-dir "$tmp/build" --output-on-failure --no-tests=error

plugins=$tmp/build/plugins
test -f "$plugins/bfs_example.so" && test -f "$plugins/bfs_example.flipper.yaml"

# The listing marks bfs_example as selected and loadable (other rows may vary with the build).
listing=$("$build/bin/flipper" plugins --set "plugin_paths=[$plugins]" --set planner.plugin=bfs_example || true)
echo "$listing"
echo "$listing" | grep -Eq "^\* bfs_example +planner +0\.1\.0 +2 \(sdk 2\.[0-9]+\) +$plugins/bfs_example\.so +ok$"

# A full check instantiates it with the kernel test plugins, and with the default config.
"$build/bin/flipper" config check --config "$src/tests/kernel/data/kernel_test.yaml" \
  --set "plugin_paths=[$plugins, $build/tests/plugins/good]" --set planner.plugin=bfs_example \
  --set planner.params=null \
  | grep -q "plugin: bfs_example"
"$build/bin/flipper" config check --set "plugin_paths=[$plugins]" --set planner.plugin=bfs_example \
  | grep -q "plugin: bfs_example"
echo "out-of-tree plugin OK"
