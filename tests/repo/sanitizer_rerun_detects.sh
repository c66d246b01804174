#!/usr/bin/env bash
# scripts/sanitizer-ctest reruns a test once only when LeakSanitizer itself crashed in it, and
# fails on everything else, on a scratch ctest project whose tests print what instrumented tests
# print (docs/testing.md, "Fuzzing and sanitizers"). Each test counts its runs in a file.
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "sanitizer_rerun_detects: $*" >&2; exit 1; }
crash='echo "Tracer caught signal 11: addr=0x340"; echo "==1==LeakSanitizer has encountered a fatal error."'
leak='echo "==1==ERROR: LeakSanitizer: detected memory leaks"'
printf 'cmake_minimum_required(VERSION 3.20)\nproject(scratch NONE)\nenable_testing()\n' \
  >"$tmp/CMakeLists.txt"
scripted() {  # scripted NAME BODY: a test running BODY with $n its run number
  printf 'n=$(( $(cat %s/%s.runs 2>/dev/null || echo 0) + 1 )); echo $n >%s/%s.runs\n%s\n' \
    "$tmp" "$1" "$tmp" "$1" "$2" >"$tmp/$1.sh"
  echo "add_test(NAME $1 COMMAND bash $tmp/$1.sh)" >>"$tmp/CMakeLists.txt"
}
scripted passes "echo All tests passed"
scripted crashes_once "echo All tests passed; if [ \$n = 1 ]; then $crash; exit 1; fi"
scripted crashes_always "echo All tests passed; $crash; exit 1"
scripted leaks_and_crashes "$leak; $crash; exit 1"
scripted ub_and_crashes "echo 'a.cpp:3:7: runtime error: signed integer overflow'; $crash; exit 1"
scripted fails "echo 'FAILED:'; exit 1"
scripted options "echo \"\$ASAN_OPTIONS\" >$tmp/options"
# Last, with regular-expression characters in its name: a run given -E numbers only the tests it
# kept, so the rerun must select by name (ctest --rerun-failed reran "passes" instead).
scripted 'crash.once+1' "echo All tests passed; if [ \$n = 1 ]; then $crash; exit 1; fi"
cmake -S "$tmp" -B "$tmp/b" >/dev/null
runs() { cat "$tmp/$1.runs" 2>/dev/null || echo 0; }
case_run() {  # case_run REGEX: a fresh count, the script on the tests REGEX selects; sets rc
  case_args -R "$1"
}
case_args() {  # case_args CTEST_ARGS...: the same with those ctest arguments
  rm -f "$tmp"/*.runs
  rc=0
  bash "$src/scripts/sanitizer-ctest" "$tmp/b" "$@" >"$tmp/out" 2>&1 || rc=$?
}

case_run '^passes$'
((rc == 0)) || fail "a passing test: exit $rc"
grep -q 'run once more' "$tmp/out" && fail "a passing test was rerun"

case_run '^(passes|crashes_once)$'
((rc == 0)) || fail "LSan crashing once: exit $rc: $(cat "$tmp/out")"
[[ $(runs crashes_once) == 2 && $(runs passes) == 1 ]] ||
  fail "LSan crashing once: runs $(runs crashes_once) and $(runs passes), not 2 and 1"
grep -q '^  crashes_once$' "$tmp/out" || fail "the rerun test is not named: $(cat "$tmp/out")"

case_args -E '^(passes|crashes_once|crashes_always|leaks_and_crashes|ub_and_crashes|fails|options)$'
((rc == 0)) || fail "LSan crashing once after excluded tests: exit $rc: $(cat "$tmp/out")"
[[ $(runs crash.once+1) == 2 && $(runs passes) == 0 ]] ||
  fail "the rerun after -E: runs $(runs crash.once+1) and $(runs passes) of passes, not 2 and 0"

case_run '^crashes_always$'
((rc != 0)) || fail "LSan crashing on every run passed"
[[ $(runs crashes_always) == 2 ]] || fail "LSan crashing on every run: $(runs crashes_always) runs"

for t in leaks_and_crashes ub_and_crashes fails; do
  case_run "^$t\$"
  ((rc != 0)) || fail "$t passed"
  [[ $(runs "$t") == 1 ]] || fail "$t was rerun"
done

case_run '^(crashes_once|fails)$'  # one other failure: no test is rerun
((rc != 0)) || fail "an LSan crash beside a failure passed"
[[ $(runs crashes_once) == 1 ]] || fail "an LSan crash beside a failure was rerun"
# The tests run with ASan's allocation stacks at 10 frames; options given to the script win.
# options_seen [ASAN_OPTIONS=...]: what the options test saw, the script run with that alone (not
# this process's own ASAN_OPTIONS: instrumented, it runs under the script itself).
options_seen() {
  env -u ASAN_OPTIONS "$@" bash "$src/scripts/sanitizer-ctest" "$tmp/b" -R '^options$' \
    >"$tmp/out" 2>&1 || { echo "(the script failed: $(cat "$tmp/out"))"; return; }
  cat "$tmp/options"
}
seen=$(options_seen)
[[ $seen == malloc_context_size=10 ]] ||
  fail "the tests' ASAN_OPTIONS: '$seen', not 'malloc_context_size=10'"
seen=$(options_seen ASAN_OPTIONS=malloc_context_size=30:detect_leaks=0)
[[ $seen == malloc_context_size=10:malloc_context_size=30:detect_leaks=0 ]] ||
  fail "ASAN_OPTIONS given to the script: '$seen'"
echo "sanitizer_rerun_detects: 10 of 10 cases as documented" >&2
