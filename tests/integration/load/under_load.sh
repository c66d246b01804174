#!/usr/bin/env bash
# Same answers on a quiet machine and at `nice -n 19` beside a busy loop (docs/planners.md §2:
# limits that can change an answer count work or the request thread's CPU time; the wall clock
# is only a far backstop). Runs, once quietly and once at nice 19 pinned (taskset) to one CPU
# on which a busy loop, pinned there too, spins at normal priority:
#   - every `build/bin/flipper run ...` line of the tested blocks of README.md and docs/usage.md
#     (the 3-D octomap-ompl example included);
#   - a small `flipper bench planners` experiment (small-planners.yaml), its results table;
# and requires byte-identical answers (stdout, exit status) and results tables. The quiet run
# must succeed (exit 0), so two equal failures do not pass.
# Measured CPU (Release, this project's 2-core machine, each command end to end with start-up):
# the study-map runs 10-20 ms, the octomap-ompl run 76 ms (execution.cpu_budget_ms 2000:
# 26x margin; a sanitizer build 2-3x slower), the bench 0.5 s (longest plan 0.15 s, bench
# cpu_budget_ms 10000). At nice 19 beside two busy loops a process got 0.16-1.4 % of a core
# (0.16 % with 8 other builds on the machine), so the loaded phase takes 70-650x its CPU in
# wall time: 0.62 s of CPU took 400 s here (the bench ~300 s of it), a sanitizer build would
# take 2-3x that. Each loaded command is bounded by `timeout` (kLimit below, 3x the slowest
# sanitizer estimate); the busy loop is killed at the end, also on failure.
# One loop on the loaded commands' one CPU starves them as much as one loop per CPU did (the
# same nice-0 loop beside them on whichever CPU they run: a 15/1039 share of it at nice 19), and
# burns one core for the loaded phase's wall instead of all of them: in Release 81 -> 47 s of
# CPU for the whole test at load 7-8 (a thread at nice 19 here got 0.6 % of the CPU); in CI,
# where it runs alone, one core-second per second of the loaded phase instead of two.
# Before CPU budgets (wall-clock deadlines, the same machine): the octomap-ompl run failed with
# deadline_exceeded and the bench's octomap3d rows fell to 50 % (rrtconnect) and 25 % (prm).
# Usage: under_load.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
kLimit=3000  # seconds per loaded command: the bench took ~300 s here, ~900 s with a sanitizer
tmp=$(mktemp -d)
burners=()
cleanup() {
  for pid in "${burners[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${burners[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() {
  echo "FAILED: $*"
  exit 1
}

# A scratch folder that looks like the repository root (as scripts/readme-figures makes it).
mkdir "$tmp/root"
ln -s "$build" "$tmp/root/build"
for d in configs data examples docs; do ln -s "$src/$d" "$tmp/root/$d"; done

# The `run` examples of README.md and docs/usage.md: lines of their tested blocks (a fence after
# `<!-- readme-test -->`), the comment after "  # " dropped.
mapfile -t commands < <(awk '
  /^<!-- readme-test -->$/ { armed = 1; next }
  armed && /^```/ { if (inside) { inside = 0; armed = 0 } else inside = 1; next }
  inside && /^build\/bin\/flipper run / { sub(/  # .*$/, ""); print }
' "$src/README.md" "$src/docs/usage.md")
((${#commands[@]} >= 3)) || fail "found ${#commands[@]} 'flipper run' lines in the tested blocks"
printf '%s\n' "${commands[@]}" | grep -q 'configs/octomap-ompl.yaml' ||
  fail "docs/usage.md's octomap-ompl example is not among the tested run lines"

run_phase() {  # run_phase NAME [PREFIX...]: every command, outputs in $tmp/NAME
  local out=$tmp/$1
  shift
  mkdir -p "$out/home"
  local i=0 status
  for c in "${commands[@]}"; do
    i=$((i + 1))
    status=0
    (cd "$tmp/root" && HOME=$out/home timeout "$kLimit" "$@" bash -c "$c") \
      >"$out/run$i.out" 2>"$out/run$i.err" || status=$?
    echo "$status" >"$out/run$i.status"
  done
  status=0
  (cd "$tmp/root" && HOME=$out/home timeout "$kLimit" "$@" build/bin/flipper bench planners \
    --experiment "$here/small-planners.yaml" --out "$out/bench" --jobs 1 --no-plots \
    --print results) >"$out/bench.out" 2>"$out/bench.err" || status=$?
  echo "$status" >"$out/bench.status"
}

TIMEFORMAT='%R s wall, %U s user CPU'
echo "== quiet"
time run_phase quiet
for i in $(seq 1 ${#commands[@]}); do
  [[ $(cat "$tmp/quiet/run$i.status") == 0 ]] ||
    fail "quiet: '${commands[i - 1]}' exited $(cat "$tmp/quiet/run$i.status"): $(cat "$tmp/quiet/run$i.err")"
done
[[ $(cat "$tmp/quiet/bench.status") == 0 ]] || fail "quiet bench: $(cat "$tmp/quiet/bench.err")"
grep -q '^| octomap3d | prm |' "$tmp/quiet/bench.out" || fail "quiet bench: no results table"

# The first CPU this script may run on (its affinity list, e.g. "0-1" or "2,5").
cpu=$(taskset -pc $$ | sed 's/.*: *//; s/[,-].*//')
[[ $cpu =~ ^[0-9]+$ ]] || fail "no CPU in this process's affinity list: $(taskset -pc $$)"
taskset -c "$cpu" bash -c 'while :; do :; done' &
burners+=($!)
echo "== nice 19 beside a busy loop, both on CPU $cpu"
time run_phase loaded taskset -c "$cpu" nice -n 19

status=0
for i in $(seq 1 ${#commands[@]}); do
  c=${commands[i - 1]}
  if ! cmp -s "$tmp/quiet/run$i.status" "$tmp/loaded/run$i.status" ||
    ! cmp -s "$tmp/quiet/run$i.out" "$tmp/loaded/run$i.out"; then
    echo "DIFFERS under load: $c (exit $(cat "$tmp/loaded/run$i.status"))"
    diff "$tmp/quiet/run$i.out" "$tmp/loaded/run$i.out" | head -20 || true
    head -c 600 "$tmp/loaded/run$i.err"
    status=1
  else
    echo "same: $c"
  fi
done
if ! cmp -s "$tmp/quiet/bench.status" "$tmp/loaded/bench.status" ||
  ! cmp -s "$tmp/quiet/bench.out" "$tmp/loaded/bench.out"; then
  echo "DIFFERS under load: the bench's results table (exit $(cat "$tmp/loaded/bench.status"))"
  diff "$tmp/quiet/bench.out" "$tmp/loaded/bench.out" || true
  head -c 600 "$tmp/loaded/bench.err"
  status=1
else
  echo "same: the bench's results table"
fi
((status == 0)) || fail "answers differ between a quiet run and nice 19 under load"
echo "PASSED"
