#!/usr/bin/env bash
# Installed-binary check: install everything into a temp prefix, then run the installed flipper
# from a folder outside the source and build trees. It must hold no source or build path, list
# only its own plugins (<prefix>/lib/flipper/plugins), resolve the default config against
# <prefix>/share/flipper/configs and answer a query with them, and draw a replay's plots with the
# scripts in <prefix>/share/flipper/plots.
# Usage: installed.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
flipper=$tmp/prefix/bin/flipper
frontends=$tmp/prefix/lib/flipper/frontends  # the serve and dds modules flipper loads
plugins=$tmp/prefix/lib/flipper/plugins
cd "$tmp"

# No path of this checkout or its build is compiled in, absolute or (as __FILE__ is under a
# compiler cache with a base folder) relative to the build tree.
for bin in "$flipper" "$frontends"/*.so "$plugins"/*.so; do
  for dir in "$src" "$build"; do
    if grep -aFq "$dir" "$bin"; then
      echo "installed $bin contains the path $dir:"; grep -aoF "$dir" "$bin" | head -3
      exit 1
    fi
  done
  if source_file=$(grep -m1 -aoE '(^|[^A-Za-z0-9_])[.][.]/[A-Za-z0-9_./-]+[.](cpp|hpp|cc|h)' "$bin" | tr -d '\000'); then
    echo "installed $bin contains the source path $source_file (a __FILE__ of ours?)"
    exit 1
  fi
done

# Every listed plugin comes from the prefix.
listing=$(env -u FLIPPER_PLUGIN_PATH "$flipper" plugins)
echo "$listing"
echo "$listing" | grep -Eq "^\* astar +planner .* $plugins/astar\.so +ok$"
if echo "$listing" | grep -F "$build"; then echo "a plugin of the build tree was listed"; exit 1; fi

env -u FLIPPER_PLUGIN_PATH "$flipper" config check >/dev/null
answer=$(echo '{"op":"query","text":"move up"}' | env -u FLIPPER_PLUGIN_PATH "$flipper" session)
echo "$answer" | grep -q '"ok":true'

# `plugin new` from the installed binary points the scaffold at the installed SDK beside it.
"$flipper" plugin new planner my_planner "$tmp/my_planner" >/dev/null
grep -qF -- "-DCMAKE_PREFIX_PATH=$tmp/prefix" "$tmp/my_planner/README.md"

# serve runs in the installed serve module, which finds the installed page.
env -u FLIPPER_PLUGIN_PATH "$flipper" serve --set serve.port=0 >serve.log 2>&1 &
serve_pid=$!
for _ in $(seq 600); do grep -qs "listening" serve.log && break; sleep 0.1; done
kill "$serve_pid"; wait "$serve_pid" || true
cat serve.log
grep -q "^flipper serve: listening on http://127.0.0.1:[0-9]*/$" serve.log

# A replay run in a folder outside both trees: the installed plot scripts draw its plots (the
# corpus is the source's data, which is not installed).
env -u FLIPPER_PLUGIN_PATH "$flipper" replay --corpus "$src/tests/apps/replay/data" --out runs >replay.log 2>&1
cat replay.log
grep -q "^plots: .* in runs/replay-" replay.log
test -f runs/latest/plain/tokens.pdf

# The embedded default config's files are the installed ones: without the installed world file
# the binary names that file (and finds no other).
rm "$tmp/prefix/share/flipper/configs/worlds/study2018.json"
if out=$(echo '{"op":"query","text":"move up"}' | env -u FLIPPER_PLUGIN_PATH "$flipper" session 2>&1); then
  echo "the session started without the installed world file: $out"; exit 1
fi
echo "$out"
echo "$out" | grep -qF "$tmp/prefix/share/flipper/configs/worlds/study2018.json"
echo "installed flipper OK"
