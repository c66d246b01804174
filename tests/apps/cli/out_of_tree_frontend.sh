#!/usr/bin/env bash
# An out-of-tree front end against an installed SDK (docs/architecture.md §1 "Front ends are
# modules"):
# 1. install the SDK (component "sdk") into a temp prefix; it carries examples/out-of-tree-frontend;
# 2. build a copy of the installed example against that prefix alone (warnings are errors);
# 3. serve it with build/bin/flipper (`flipper frontend lines`) on a free loopback port; the answers
#    to a session script over TCP are `flipper session`'s answers to it, byte for byte, and a second
#    connection is a session of its own;
# 4. SIGTERM stops it (exit 0, "stopped after N requests");
# 5. refusals: a parameter out of range or misspelt, an unknown front end, a planner asked to be a
#    front end (exit 2, the messages of the plugin loader and the schema check).
# Usage: out_of_tree_frontend.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
flipper=$build/bin/flipper
tmp=$(mktemp -d)
server_pid=
cleanup() {
  if [ -n "$server_pid" ]; then kill "$server_pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() {
  echo "FAILED: $*"
  exit 1
}

echo "== 1. install the SDK component"
prefix=$tmp/prefix
cmake --install "$build" --component sdk --prefix "$prefix" >/dev/null
example=$prefix/share/flipper/examples/out-of-tree-frontend
test -f "$example/CMakeLists.txt" || fail "the SDK install lacks the front-end example"
test -f "$prefix/include/flipper/sdk/frontend.hpp" || fail "the SDK install lacks frontend.hpp"

echo "== 2. build the installed example against the prefix alone"
cp -r "$example" "$tmp/example"
cmake -S "$tmp/example" -B "$tmp/example-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_CXX_FLAGS=-Werror >/dev/null
cmake --build "$tmp/example-build" -j2
plugins=$tmp/example-build/plugins
test -f "$plugins/lines.so" && test -f "$plugins/lines.flipper.yaml"
grep -qx "kind: frontend" "$plugins/lines.flipper.yaml" || fail "the sidecar's kind"

echo "== 3. flipper serves it; its answers are flipper session's"
common=(--set "plugin_paths=[$plugins]" --set lexicon.path=:memory:)
# The logs exist before the server starts: the background job opens its redirections after the fork,
# so the first poll below could otherwise run before err.log exists (seen under load).
: >"$tmp/out.log"
: >"$tmp/err.log"
"$flipper" frontend lines "${common[@]}" --param port=0 >"$tmp/out.log" 2>"$tmp/err.log" &
server_pid=$!
port=
for _ in $(seq 600); do  # up to 60 s for the line that names the port
  port=$(sed -n 's/^flipper frontend lines: listening on 127\.0\.0\.1:\([0-9]*\)$/\1/p' "$tmp/err.log")
  [ -n "$port" ] && break
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
[ -n "$port" ] || { cat "$tmp/err.log"; fail "no 'listening on 127.0.0.1:PORT' line"; }
# The example session, then a move that is accepted (the robot moves).
script=$tmp/script.jsonl
{ cat "$src/examples/session.jsonl"
  printf '%s\n' '{"op":"query","text":"move up"}' '{"op":"accept","rank":0}'; } >"$script"
"$flipper" session "${common[@]}" <"$script" | sed 's/"ms":[0-9.e-]*/"ms":_/g' >"$tmp/expected"
lines=$(wc -l <"$tmp/expected")
[ "$lines" -eq 8 ] || fail "flipper session answered $lines of 8 requests"
exchange() {  # exchange <fd> <requests file> <answers out> <count>, on an open connection
  cat "$2" >&"$1"
  timeout 60 head -n "$4" <&"$1" | sed 's/"ms":[0-9.e-]*/"ms":_/g' >"$3"
}
exec 3<>"/dev/tcp/127.0.0.1/$port"
exchange 3 "$script" "$tmp/got" 8
diff -u "$tmp/expected" "$tmp/got" || fail "the front end's answers differ from flipper session's"
# A second connection is a session of its own: its robot is where the config's world puts it, not where
# the first connection moved it (the oracle of the reused session answers differently: checked).
printf '%s\n' '{"op":"query","text":"move up"}' >"$tmp/query"
"$flipper" session "${common[@]}" <"$tmp/query" | sed 's/"ms":[0-9.e-]*/"ms":_/g' >"$tmp/expected2"
{ cat "$script" "$tmp/query"; } | "$flipper" session "${common[@]}" | tail -1 |
  sed 's/"ms":[0-9.e-]*/"ms":_/g' >"$tmp/reused"
if cmp -s "$tmp/expected2" "$tmp/reused"; then fail "the oracle cannot tell sessions apart"; fi
exec 4<>"/dev/tcp/127.0.0.1/$port"  # while the first is still open
exchange 4 "$tmp/query" "$tmp/got2" 1
exec 3>&- 4>&-
diff -u "$tmp/expected2" "$tmp/got2" || fail "a second connection is not a fresh session"

echo "== 4. SIGTERM stops it"
kill -TERM "$server_pid"
status=0
wait "$server_pid" || status=$?
server_pid=
[ "$status" -eq 0 ] || { cat "$tmp/err.log"; fail "exit status $status after SIGTERM"; }
grep -qx "flipper frontend lines: stopped after 9 requests" "$tmp/err.log" ||
  { cat "$tmp/err.log"; fail "no 'stopped after 9 requests' line"; }

echo "== 5. refusals"
refused() {  # refused <expected stderr> <args...>
  local want=$1
  shift
  local got status=0
  got=$("$flipper" frontend "$@" 2>&1 >/dev/null) || status=$?
  [ "$status" -eq 2 ] || fail "flipper frontend $* exited $status, not 2: $got"
  [ "$got" = "$want" ] || fail "flipper frontend $*: expected '$want', got '$got'"
}
refused "flipper frontend: [bad_config] config key 'frontend.lines.port' = 65536 is out of range [0, 65535]" \
  lines --set "plugin_paths=[$plugins]" --param port=65536
refused "flipper frontend: [bad_config] unknown config key 'frontend.lines.prot' (did you mean 'frontend.lines.port'?); keys in 'frontend.lines': host, port, max_line_bytes" \
  lines --set "plugin_paths=[$plugins]" --param prot=7
refused "flipper frontend: [bad_config] config key 'frontend.lines.port' = 'x' must be an integer" \
  lines --set "plugin_paths=[$plugins]" --param port=x
searched="searched: $build/lib/flipper/frontends, $plugins, $build/plugins"
refused "flipper frontend: [plugin_not_found] no frontend plugin named 'line'; available frontend plugins: dds, serve, lines; $searched" \
  line --set "plugin_paths=[$plugins]"
refused "flipper frontend: [plugin_not_found] plugin 'astar' ($build/plugins/astar.so) is a planner plugin, not a frontend plugin; available frontend plugins: dds, serve, lines; $searched" \
  astar --set "plugin_paths=[$plugins]"
echo "all passed"
