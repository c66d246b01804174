#!/usr/bin/env bash
# scripts/lint fails on what it is there to catch (docs/architecture.md §2, README "Set up and
# test"): it runs, as CI runs it, on a scratch tree holding the repository's .clang-format and
# .clang-tidy and one small source file, clean and then broken in three ways.
# Usage: lint_detects.sh <repository root>
set -euo pipefail
root=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scripts" "$tmp/apps/demo" "$tmp/build"
cp "$root/scripts/lint" "$tmp/scripts/"
cp "$root/.clang-format" "$root/.clang-tidy" "$tmp/"
commands() {  # commands FILE...: build/compile_commands.json, each FILE compiled alone
  local f sep="["
  for f in "$@"; do
    printf '%s{"directory": "%s", "file": "%s",\n  "command": "clang++-14 -std=c++20 -c %s -o /dev/null"}' \
      "$sep" "$tmp" "$f" "$f"
    sep=$',\n '
  done >"$tmp/build/compile_commands.json"
  printf ']\n' >>"$tmp/build/compile_commands.json"
}
commands "$tmp/apps/demo/demo.cpp"
clean() {
  cat >"$tmp/apps/demo/demo.cpp" <<'CPP'
#include <string>
#include <utility>

std::string keep(const std::string& text) {
  return text + "!";
}

std::string twice(std::string text) {
  std::string copy = std::move(text);
  return copy + copy;
}
CPP
}
expect() {  # expect pass|fail <what> <lint args...>
  local want=$1 what=$2 result=pass
  shift 2
  (cd "$tmp" && bash scripts/lint "$@" >"$tmp/out" 2>&1) || result=fail
  if [[ $result != "$want" ]]; then
    echo "expected scripts/lint $* to $want for: $what"
    cat "$tmp/out"
    exit 1
  fi
  echo "$want as expected: $what"
}
clean
expect pass "a formatted, clean file" build
printf 'int  badly_spaced ( ) { return 1 ; }\n' >>"$tmp/apps/demo/demo.cpp"
expect fail "an unformatted line" --format-only
clean
cat >>"$tmp/apps/demo/demo.cpp" <<'CPP'

std::size_t moved_then_used(std::string text) {
  std::string other = std::move(text);
  return other.size() + text.size();
}
CPP
expect fail "a use after move" --tidy-only build
grep -q 'bugprone-use-after-move' "$tmp/out" || { echo "no use-after-move finding named"; exit 1; }
clean
cat >>"$tmp/apps/demo/demo.cpp" <<'CPP'

std::size_t only_read(std::string text) {
  return text.size();
}
CPP
expect fail "a parameter copied where a reference does" --tidy-only build
grep -q 'performance-unnecessary-value-param' "$tmp/out" || { echo "no value-param finding"; exit 1; }
clean
cat >>"$tmp/apps/demo/demo.cpp" <<'CPP'

long cells(int width, int height) {
  return width * height;
}
CPP
expect fail "an int multiplication widened after the fact" --tidy-only build
grep -q 'implicit-widening-of-multiplication-result' "$tmp/out" || { echo "no widening finding"; exit 1; }

# --changed-since REF (scripts/test outside CI): only the units a change since REF can affect.
# A committed unit with a finding is skipped while unchanged; a unit is checked when it changed
# or when its dependency file (or Ninja's log) names a changed header.
clean
printf '#pragma once\nint answer();\n' >"$tmp/apps/demo/demo.hpp"
printf '#include "demo.hpp"\n' | cat - "$tmp/apps/demo/demo.cpp" >"$tmp/demo.tmp"
mv "$tmp/demo.tmp" "$tmp/apps/demo/demo.cpp"
cat >"$tmp/apps/demo/old.cpp" <<'CPP'
long cells(int width, int height) {
  return width * height;
}
CPP
commands "$tmp/apps/demo/demo.cpp" "$tmp/apps/demo/old.cpp"
printf 'demo.cpp.o: \\\n %s %s\n' "$tmp/apps/demo/demo.cpp" "$tmp/apps/demo/demo.hpp" >"$tmp/build/demo.cpp.o.d"
printf "build/\nout\n" >"$tmp/.gitignore"
git -C "$tmp" init -q
git -C "$tmp" add -A
git -C "$tmp" -c user.name=lint -c user.email=lint@localhost commit -qm base
expect fail "a finding in a committed unit, every unit checked" --tidy-only build
expect pass "the same finding, its unit unchanged since the base" --tidy-only --changed-since HEAD build
grep -q 'clang-tidy on 0 of 2 units' "$tmp/out" || { echo "units were checked"; cat "$tmp/out"; exit 1; }
printf 'int other();\n' >>"$tmp/apps/demo/demo.hpp"
expect pass "a changed header: the unit including it is checked" --tidy-only --changed-since HEAD build
grep -q 'clang-tidy on 1 of 2 units' "$tmp/out" || { echo "not the header's unit"; cat "$tmp/out"; exit 1; }
# The same in a Ninja build (-G Ninja): no *.o.d files, the dependencies are in Ninja's log, with
# paths relative to the build folder. A one-rule build.ninja records them as a compile would.
rm "$tmp/build/demo.cpp.o.d"
cat >"$tmp/build/build.ninja" <<'NINJA'
rule cc
  command = printf '%s: ../apps/demo/demo.cpp ../apps/demo/demo.hpp\n' $out > $out.d && touch $out
  depfile = $out.d
  deps = gcc
build demo.cpp.o: cc ../apps/demo/demo.cpp
NINJA
ninja -C "$tmp/build" >/dev/null
expect pass "a changed header, Ninja's log: the unit including it is checked" \
  --tidy-only --changed-since HEAD build
grep -q 'clang-tidy on 1 of 2 units' "$tmp/out" ||
  { echo "not the header's unit (Ninja)"; cat "$tmp/out"; exit 1; }
printf '// touched\n' >>"$tmp/apps/demo/old.cpp"
expect fail "the unit with the finding changed" --tidy-only --changed-since HEAD build
grep -q 'implicit-widening-of-multiplication-result' "$tmp/out" || { echo "no widening finding"; exit 1; }

# A unity batch (the product's FLIPPER_UNITY): its units are checked through the batch, in one run,
# and a finding names the unit's own file. A batch that also holds a test unit (a test executable
# built from a product source) does not stand for its product units: those are checked alone,
# and the test unit's findings (Catch2's macros trip the checks by design) are not reported.
mkdir -p "$tmp/build/Unity" "$tmp/tests/apps/demo"
printf '#include "%s"\n#include "%s"\n' "$tmp/apps/demo/demo.cpp" "$tmp/apps/demo/old.cpp" \
  >"$tmp/build/Unity/unity_0_cxx.cxx"
commands "$tmp/build/Unity/unity_0_cxx.cxx"
expect fail "a finding in a unit of a unity batch" --tidy-only build
grep -q 'apps/demo/old.cpp:2:.*implicit-widening-of-multiplication-result' "$tmp/out" ||
  { echo "the finding does not name the unit's line"; cat "$tmp/out"; exit 1; }
printf 'long cells(int width, int height) {\n  return long{width} * height;\n}\n' >"$tmp/apps/demo/old.cpp"
expect pass "the batch's units clean" --tidy-only build
grep -q 'clang-tidy clean (2 translation units, in 1 runs)' "$tmp/out" ||
  { echo "not one run for the batch"; cat "$tmp/out"; exit 1; }
cat >"$tmp/tests/apps/demo/test_demo.cpp" <<'CPP'
long test_cells(int width, int height) {
  return width * height;
}
CPP
printf '#include "%s"\n#include "%s"\n' "$tmp/apps/demo/old.cpp" "$tmp/tests/apps/demo/test_demo.cpp" \
  >"$tmp/build/Unity/unity_1_cxx.cxx"
commands "$tmp/build/Unity/unity_0_cxx.cxx" "$tmp/build/Unity/unity_1_cxx.cxx"
printf '#include "%s"\n' "$tmp/apps/demo/demo.cpp" >"$tmp/build/Unity/unity_0_cxx.cxx"
git -C "$tmp" add -A
expect pass "a product unit in a test's batch only: checked alone" --tidy-only build
grep -q 'clang-tidy clean (2 translation units, in 2 runs)' "$tmp/out" ||
  { echo "not the batch and the unit alone"; cat "$tmp/out"; exit 1; }
