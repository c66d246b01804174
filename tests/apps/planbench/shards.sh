#!/usr/bin/env bash
# `flipper bench planners --shard I/N` and `bench planners merge` end to end (docs/planners.md §5,
# "Shards"), on the maze with astar (no seed) and ompl's rrtconnect (seeds 1 and 2), one world
# with hand-drawn tasks and one with random ones: 6 cells, 24 plans.
# 1. for N = 1, 2, 3, 24 (the number of plans) and 25: every shard run holds exactly the rows
#    r of the whole run with r mod N = I, and the merge of the N shards equals one unsharded run
#    byte for byte: tasks.csv, variants.csv, settings.csv, runs.csv, figures.csv and
#    intervals.csv (measured columns, timing figures and rows left out in both), report.md up
#    to its timing section; the merged runs.csv takes each shard's lines unchanged;
# 2. `--shard` values that are not I/N with 0 <= I < N exit 2 with a message, no run folder;
# 3. merges that cannot be one run exit 2 naming why: a shard missing or given twice, a run
#    that is no shard, shards of different N, a shard still running; no merged folder is left;
# 4. `bench planners check` re-runs a shard as a shard, a merged run as a whole one (exit 0);
# 5. with a planner that segfaults on every call (tests/support/evil_planner): the 3 shards
#    merged equal the whole run, its lost tasks in the same order (report, manifest), exit 1.
# Usage: shards.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
flipper=$build/bin/flipper
data=$src/tests/apps/planbench/data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAILED: $*"
  exit 1
}

cat >"$tmp/grid.yaml" <<YAML
name: shards
seeds: [1, 2]
worlds:
  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $data/maze-tasks.yaml}}
  - {name: maze_random, plugin: grid2d, file: $data/maze.json, tasks: {random: 3, seed: 7}}
planners:
  - {plugin: astar}
  - {name: rrtconnect, plugin: ompl, params: {planner: rrtconnect}}
YAML
bench() { "$flipper" bench planners --experiment "$tmp/grid.yaml" --no-plots --jobs 2 "$@"; }

echo "== 1. the whole run, then N shards merged, for N = 1, 2, 3, 24, 25"
bench --out "$tmp/whole" >/dev/null
whole=$(readlink -f "$tmp/whole/latest")
[[ $(($(wc -l <"$whole/runs.csv") - 1)) == 24 ]] || fail "the whole run has not 24 plans"
for n in 1 2 3 24 25; do
  for ((i = 0; i < n; i++)); do bench --out "$tmp/n$n" --shard "$i/$n" >/dev/null; done
  "$flipper" bench planners merge "$tmp/n$n"/grid-shard*of"$n"-* --out "$tmp/m$n" --no-plots \
    >"$tmp/m$n.out"
  grep -q "^merged $n shards$" "$tmp/m$n.out" || fail "merge of $n: $(cat "$tmp/m$n.out")"
  merged=$(readlink -f "$tmp/m$n/latest")
  [[ $merged == */grid-merged-* ]] || fail "merged run folder $merged"
  python3 - "$whole" "$merged" "$n" "$tmp/n$n" <<'PY'
import csv, glob, io, json, os, sys
whole, merged, n, shards = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
def fail(msg):
    print("FAILED: N=%d: %s" % (n, msg)); sys.exit(1)
def text(run, name):
    return open(os.path.join(run, name), "rb").read()
for name in ("tasks.csv", "variants.csv", "settings.csv"):
    if text(whole, name) != text(merged, name): fail(name + " differs")
measured = {"cpu_us", "wall_us", "peak_rss_kib", "memory_kib"}
def blank_measured(data):  # the file's own lines, measured fields emptied in place
    lines = data.decode().splitlines(keepends=True)
    header = next(csv.reader([lines[0]]))
    idx = [i for i, h in enumerate(header) if h in measured]
    out = [lines[0]]
    for line in lines[1:]:
        row = next(csv.reader([line]))
        for i in idx: row[i] = ""
        s = io.StringIO(); csv.writer(s, lineterminator="\n").writerow(row); out.append(s.getvalue())
    return "".join(out)
if blank_measured(text(whole, "runs.csv")) != blank_measured(text(merged, "runs.csv")):
    fail("runs.csv differs in a deterministic column")
def deterministic_figures(run):
    return b"".join(l for l in text(run, "figures.csv").splitlines(True) if not l.rstrip().endswith(b",1"))
if deterministic_figures(whole) != deterministic_figures(merged): fail("figures.csv differs")
def deterministic_intervals(run):
    return b"".join(l for l in text(run, "intervals.csv").splitlines(True) if not l.rstrip().endswith(b",1"))
if deterministic_intervals(whole) != deterministic_intervals(merged): fail("intervals.csv differs")
def before_timing(run):
    r = text(run, "report.md"); return r[:r.index(b"## Timing (measured)")]
if before_timing(whole) != before_timing(merged): fail("report.md differs before its timing section")
# Each shard holds exactly rows r with r mod N = I, and the merge takes its lines unchanged.
merged_lines = text(merged, "runs.csv").splitlines(True)
runs = sorted(glob.glob(os.path.join(shards, "grid-shard*of%d-*" % n)))
if len(runs) != n: fail("%d shard runs" % len(runs))
for run in runs:
    m = json.load(open(os.path.join(run, "manifest.json")))
    i = m["shard"]["index"]
    if m["shard"] != {"index": i, "count": n} or m["status"] != "complete":
        fail("%s: shard %s, status %s" % (run, m["shard"], m["status"]))
    if not os.path.basename(run).startswith("grid-shard%dof%d-" % (i, n)): fail("folder " + run)
    lines = text(run, "runs.csv").splitlines(True)
    want = [merged_lines[1 + r] for r in range(24) if r % n == i]
    if lines[0] != merged_lines[0] or lines[1:] != want:
        fail("shard %d's rows are not the rows r mod %d = %d of the merged run" % (i, n, i))
m = json.load(open(os.path.join(merged, "manifest.json")))
if m["shard"] is not None or m["status"] != "complete" or len(m["merged_from"]) != n:
    fail("merged manifest: shard %s, status %s, %d merged_from" % (m["shard"], m["status"], len(m["merged_from"])))
if sorted(s["shard"]["index"] for s in m["merged_from"]) != list(range(n)): fail("merged_from")
print("N=%d: %d shards merged equal the whole run" % (n, n))
PY
done
# The empty shard (N = 25: shard 24 has no plan) is a complete run of no rows.
[[ $(wc -l <"$(ls -d "$tmp"/n25/grid-shard24of25-*)/runs.csv") == 1 ]] || fail "shard 24 of 25 has rows"

echo "== 2. bad --shard values exit 2, no run folder"
for bad in 0/0 3/2 2/2 -1/2 junk 1/ /2 1/2/3 "1 /2"; do
  status=0
  bench --out "$tmp/bad" --shard "$bad" >"$tmp/bad.out" 2>"$tmp/bad.err" || status=$?
  [[ $status == 2 ]] || fail "--shard '$bad' exited $status, not 2"
  grep -q "^flipper bench planners: \[bad_request\] --shard '$bad': " "$tmp/bad.err" ||
    fail "--shard '$bad': $(cat "$tmp/bad.err")"
  [[ ! -e $tmp/bad ]] || fail "--shard '$bad' made a run folder"
done
grep -q "I must be from 0 to 1" <(bench --out "$tmp/bad" --shard 3/2 2>&1) || fail "3/2 message"
grep -q "N must be at least 1" <(bench --out "$tmp/bad" --shard 0/0 2>&1) || fail "0/0 message"

echo "== 3. merges that are not one run exit 2"
refuse() {  # refuse MESSAGE RUN...
  local want=$1 status=0
  shift
  "$flipper" bench planners merge "$@" --out "$tmp/refused" --no-plots >/dev/null 2>"$tmp/r.err" ||
    status=$?
  [[ $status == 2 ]] || fail "merge of $* exited $status, not 2"
  grep -qF "$want" "$tmp/r.err" || fail "merge: '$(cat "$tmp/r.err")' lacks '$want'"
  [[ ! -e $tmp/refused ]] || fail "a refused merge made a folder"
}
s3=("$tmp"/n3/grid-shard*of3-*)
refuse "shard(s) 2 of 3 missing" "${s3[0]}" "${s3[1]}"
refuse "shard 1 is given twice" "${s3[0]}" "${s3[1]}" "${s3[1]}" "${s3[2]}"
refuse "is not a shard (it ran without --shard I/N)" "$whole" "${s3[1]}"
refuse "is a shard of 2," "${s3[0]}" "$(ls -d "$tmp"/n2/grid-shard1of2-*)"
refuse "is not a run folder" "$tmp/nothing"
cp -r "${s3[2]}" "$tmp/running"
python3 - "$tmp/running/manifest.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1])); m["status"] = "running"; json.dump(m, open(sys.argv[1], "w"))
PY
refuse "has not finished (status running)" "${s3[0]}" "${s3[1]}" "$tmp/running"

echo "== 4. check re-runs a shard as a shard, a merged run whole"
"$flipper" bench planners check "${s3[1]}" --jobs 2 >"$tmp/check.out" ||
  fail "check of a shard: $(cat "$tmp/check.out")"
grep -q "^re-run: .*/grid-shard1of3-" <("$flipper" bench planners check "${s3[1]}" --jobs 2 \
  --out "$tmp/rerun") || fail "the check of shard 1 of 3 did not re-run it as a shard"
"$flipper" bench planners check "$(readlink -f "$tmp/m3/latest")" --jobs 2 >"$tmp/check.out" ||
  fail "check of a merged run: $(cat "$tmp/check.out")"
echo "== 5. lost tasks merged in the whole run's order"
evil=$build/tests/plugins/evil
test -f "$evil/evil_planner.so" || fail "build the fixture: --target flipper_plugin_evil_planner"
cat >"$tmp/crash.yaml" <<YAML
name: crashing
plugin_paths: [$evil]
worlds:
  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $data/maze-tasks.yaml}}
planners:
  - {plugin: astar}
  - {name: segv, plugin: evil_planner, params: {mode: segv}}
YAML
crash() {
  local status=0
  "$flipper" bench planners --experiment "$tmp/crash.yaml" --no-plots --jobs 2 "$@" >/dev/null \
    2>&1 || status=$?
  echo $status
}
[[ $(crash --out "$tmp/cwhole") == 1 ]] || fail "the crashing run did not exit 1"
for i in 0 1 2; do crash --out "$tmp/cshards" --shard "$i/3" >/dev/null; done
status=0
"$flipper" bench planners merge "$tmp"/cshards/crash-shard* --out "$tmp/cmerged" --no-plots \
  >/dev/null 2>"$tmp/cmerge.err" || status=$?
[[ $status == 1 ]] || fail "the merge of crashing shards exited $status, not 1"
grep -q "^flipper bench planners: 5 task(s) lost their process (run partial" "$tmp/cmerge.err" ||
  fail "merge: $(cat "$tmp/cmerge.err")"
python3 - "$(readlink -f "$tmp/cwhole/latest")" "$(readlink -f "$tmp/cmerged/latest")" <<'PY'
import json, os, sys
whole, merged = sys.argv[1:3]
def fail(msg):
    print("FAILED: crashing: " + msg); sys.exit(1)
def report(run):
    r = open(os.path.join(run, "report.md"), "rb").read(); return r[:r.index(b"## Timing (measured)")]
if b"## Failed tasks" not in report(whole): fail("no failed tasks in the whole run")
if report(whole) != report(merged): fail("report.md differs before its timing section")
a, b = (json.load(open(os.path.join(r, "manifest.json"))) for r in (whole, merged))
if a["status"] != "partial" or b["status"] != "partial": fail("status %s, %s" % (a["status"], b["status"]))
if [f["task"] for f in a["failed"]] != ["corner", "around", "back", "pocket", "cut_off"]: fail("whole's failed list")
if a["failed"] != b["failed"]: fail("failed lists differ: %s vs %s" % (a["failed"], b["failed"]))
PY
echo "shards: ok"
