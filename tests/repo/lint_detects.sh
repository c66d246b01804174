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
cat >"$tmp/build/compile_commands.json" <<JSON
[{"directory": "$tmp", "file": "$tmp/apps/demo/demo.cpp",
  "command": "clang++-14 -std=c++20 -c $tmp/apps/demo/demo.cpp -o /dev/null"}]
JSON
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
