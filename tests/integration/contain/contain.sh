#!/usr/bin/env bash
# A plugin that crashes, aborts or hangs costs one task (bench planners) or one variant (replay),
# never the run (docs/experiments.md §4, docs/planners.md §5). With the evil_planner fixture
# (tests/support/evil_planner: misbehaves on the Nth plan() call of its process only):
# 1. bench planners, --jobs 1 and --jobs 2: the run finishes with exit 1, manifest `status:
#    partial` listing exactly the lost tasks (plugin_crashed SIGSEGV / SIGABRT, wall_backstop),
#    those tasks' rows with their cause, every other row as a clean run gives it, report and
#    figures; `latest` moves to it;
# 2. a run killed while running leaves `latest` where it was (its manifest is not final);
# 3. replay, --jobs 1 and --jobs 2: the crashing and hanging variants are listed as failed with
#    their cause, the healthy variant's figures equal a run of it alone;
# 4. the manifest says what ran: the source tree's commit and dirty state as git says them now
#    (not as they were at build time), the library versions as pkg-config says them, the Python
#    and matplotlib that drew the plots, and an out-of-tree `astar` that shadows the in-tree one
#    flagged with the file it hides;
# 5. `bench planners resume` finishes an interrupted run in its folder: rows kept (a row cut short
#    dropped), a changed input refused, the rest run as the rules say, `latest` moved at the end;
# 6. `runs list` shows the finished and the killed run, `runs show` the lost tasks,
#    `bench planners compare` finds no difference between --jobs 1 and 2 and says when two runs
#    share nothing (exit 1), `bench planners check` re-runs a run from its manifest: no
#    difference, then a figure changed by hand named (exit 1);
# 7. --jobs 0 is refused (exit 2) by both.
# Usage: contain.sh <source dir> <build dir>
set -euo pipefail
src=$(cd "$1" && pwd -P)
build=$(cd "$2" && pwd -P)
flipper=$build/bin/flipper
evil=$build/tests/plugins/evil
data=$src/tests/apps/planbench/data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAILED: $*"
  exit 1
}
test -f "$evil/evil_planner.so" || fail "build the fixture: --target flipper_plugin_evil_planner"

# The backstop: a healthy task here plans in well under a millisecond; a hang is killed after 2 s.
cat >"$tmp/bench.yaml" <<EOF
name: containment
plugin_paths: [$evil]
kill_after_s: 2
worlds:
  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $data/maze-tasks.yaml}}
planners:
  - {plugin: astar}
  - {name: segv, plugin: evil_planner, params: {mode: segv, on_call: 2}}
  - {name: abort, plugin: evil_planner, params: {mode: abort, on_call: 3}}
  - {name: hang, plugin: evil_planner, params: {mode: hang, on_call: 2}}
  - {name: good, plugin: evil_planner, params: {mode: ok}}
EOF

echo "== 1. bench planners with crashing and hanging cells, --jobs 1 and --jobs 2"
for jobs in 1 2; do
  status=0
  "$flipper" bench planners --experiment "$tmp/bench.yaml" --out "$tmp/bench$jobs" --jobs "$jobs" \
    --no-plots >"$tmp/bench$jobs.out" 2>"$tmp/bench$jobs.err" || status=$?
  cat "$tmp/bench$jobs.out" "$tmp/bench$jobs.err"
  [[ $status == 1 ]] || fail "bench planners --jobs $jobs exited $status, not 1"
  grep -q "^flipper bench planners: 5 task(s) lost their process (run partial" "$tmp/bench$jobs.err" ||
    fail "no summary of the lost tasks on stderr"
done
python3 - "$tmp/bench1" "$tmp/bench2" "$evil/evil_planner.so" <<'PY'
import csv, json, os, sys
one, two, library = sys.argv[1], sys.argv[2], os.path.realpath(sys.argv[3])
def fail(msg):
    print("FAILED:", msg); sys.exit(1)
measured = {"cpu_us", "wall_us", "peak_rss_kib", "memory_kib"}
# Counted by hand: the evil planner misbehaves on the Nth call of its process; a lost task's
# cell goes on with the next task in a new process, whose count starts again. Tasks, in order:
# corner, around, back, pocket, cut_off.
#   segv on 2: corner ok, around dies; back ok, pocket dies; cut_off ok
#   abort on 3: corner, around ok, back dies; pocket, cut_off ok
#   hang on 2: like segv, each hang killed by the backstop
lost = {("segv", "around"): ("plugin_crashed", "SIGSEGV"),
        ("segv", "pocket"): ("plugin_crashed", "SIGSEGV"),
        ("abort", "back"): ("plugin_crashed", "SIGABRT"),
        ("hang", "around"): ("wall_backstop", "killed after 2 s"),
        ("hang", "pocket"): ("wall_backstop", "killed after 2 s")}
tables = []
for run in (one, two):
    latest = os.path.realpath(os.path.join(run, "latest"))
    folders = [d for d in os.listdir(run) if d != "latest"]
    if len(folders) != 1: fail("run folders under %s: %s" % (run, folders))
    folder = os.path.join(run, folders[0])
    if latest != os.path.realpath(folder): fail("latest is not the finished run")
    rows = list(csv.DictReader(open(os.path.join(folder, "runs.csv"))))
    if len(rows) != 25: fail("%d rows, not 5 planners x 5 tasks" % len(rows))
    # Every other task: what the same planner gives in a clean process (astar and `good` are
    # breadth-first optimal on this maze; the evil planner plans breadth-first until it misbehaves).
    clean = {r["task"]: r for r in rows if r["planner"] == "good"}
    for r in rows:
        key = (r["planner"], r["task"])
        if key in lost:
            want = lost[key]
            if (r["status"], r["cause"], r["success"], r["length"], r["cpu_us"]) != (want[0], want[1], "0", "", ""):
                fail("lost task row %s: %s" % (key, r))
            continue
        if r["cause"] != "": fail("a cause on a healthy row: %s" % r)
        g = clean[r["task"]]
        for col in ("status", "success", "length", "shortest", "turns"):
            if r[col] != g[col]: fail("%s %s: %s %s, clean %s" % (key + (col, r[col], g[col])))
        if r["task"] == "cut_off":
            if r["status"] != "no_path": fail("cut_off: %s" % r)
        elif r["status"] != "found": fail("not found: %s" % r)
    m = json.load(open(os.path.join(folder, "manifest.json")))
    if m["status"] != "partial": fail("manifest status %s" % m["status"])
    got = sorted((f["planner"], f["task"], f["status"]) for f in m["failed"])
    if got != sorted((p, t, s) for (p, t), (s, _) in lost.items()):
        fail("manifest failed list %s" % got)
    for f in m["failed"]:
        if f["status"] == "plugin_crashed":
            sig = lost[(f["planner"], f["task"])][1]
            want = "plugin_crashed: plugin 'evil_planner' (%s): plan: %s" % (library, sig)
            if f["cause"] != want: fail("cause %r, want %r" % (f["cause"], want))
        elif f["cause"] != "wall_backstop: still running at the wall-clock backstop, in plugin 'evil_planner' (%s): plan" % library:
            fail("backstop cause %r" % f["cause"])
    report = open(os.path.join(folder, "report.md")).read()
    if report.find("## Failed tasks") < 0 or report.find("## Failed tasks") > report.find("## Results"):
        fail("report.md does not list the failed tasks before the results")
    if "| maze | segv |  | around | plugin_crashed |" not in report: fail("report row of segv/around")
    figures = list(csv.DictReader(open(os.path.join(folder, "figures.csv"))))
    # Every cell has its figures; the lost tasks count as failures of their planner.
    success = {f["variant"]: f["value"] for f in figures if f["metric"] == "success"}
    want = {"world=maze,planner=astar": "100", "world=maze,planner=good": "100",
            "world=maze,planner=segv": "60", "world=maze,planner=abort": "80",
            "world=maze,planner=hang": "60"}
    if success != want: fail("success figures %s" % success)
    tables.append([{k: v for k, v in r.items() if k not in measured} for r in rows])
if tables[0] != tables[1]: fail("runs.csv differs between --jobs 1 and --jobs 2")
print("bench planners: containment ok")
PY

echo "== 2. a run killed while it runs leaves latest alone"
before=$(readlink "$tmp/bench1/latest")
"$flipper" bench planners --experiment "$tmp/bench.yaml" --out "$tmp/bench1" --jobs 1 --no-plots \
  >/dev/null 2>&1 &
pid=$!
# Wait (bounded) for its run folder's first manifest (status running: the folder alone may come
# before it, and a run killed in between has no manifest to list), then kill it while it runs.
for _ in $(seq 1 300); do
  [[ $(find "$tmp/bench1" -mindepth 2 -maxdepth 2 -name manifest.json | wc -l) -ge 2 ]] && break
  sleep 0.1
done
kill -KILL "$pid"
wait "$pid" 2>/dev/null || true
[[ $(find "$tmp/bench1" -mindepth 1 -maxdepth 1 -type d | wc -l) -eq 2 ]] || fail "no second run folder"
[[ $(readlink "$tmp/bench1/latest") == "$before" ]] || fail "latest moved to a run that never finished"

echo "== 3. replay with a crashing, an aborting and a hanging variant, --jobs 1 and --jobs 2"
# The first 40 queries of one study run: its `visit` commands call the planner.
corpus=$src/data/study2018/dev
evil_sets="planner.plugin=evil_planner, planner.params.on_call=1"
cat >"$tmp/replay.yaml" <<EOF
name: containment
corpus: $corpus
runs: [feb2018/groupA]
max_queries: 40
kill_after_s: 2
set: [induction.generalize=false, "plugin_paths=[$evil]"]
variants:
  - {name: plain, set: []}
  - {name: segv, set: [$evil_sets, planner.params.mode=segv]}
  - {name: abort, set: [$evil_sets, planner.params.mode=abort]}
  - {name: hang, set: [$evil_sets, planner.params.mode=hang]}
EOF
cat >"$tmp/plain.yaml" <<EOF
name: containment
corpus: $corpus
runs: [feb2018/groupA]
max_queries: 40
set: [induction.generalize=false]
variants:
  - {name: plain, set: []}
EOF
"$flipper" replay --experiment "$tmp/plain.yaml" --out "$tmp/plain" --no-plots --jobs 1 >/dev/null 2>&1
for jobs in 1 2; do
  status=0
  "$flipper" replay --experiment "$tmp/replay.yaml" --out "$tmp/replay$jobs" --jobs "$jobs" \
    --no-plots >"$tmp/replay$jobs.out" 2>"$tmp/replay$jobs.err" || status=$?
  cat "$tmp/replay$jobs.out"
  grep -v "%" "$tmp/replay$jobs.err" || true
  [[ $status == 1 ]] || fail "replay --jobs $jobs exited $status, not 1"
done
python3 - "$tmp/replay1" "$tmp/replay2" "$tmp/plain" "$evil/evil_planner.so" <<'PY'
import csv, json, os, sys
one, two, plain, library = sys.argv[1], sys.argv[2], sys.argv[3], os.path.realpath(sys.argv[4])
def fail(msg):
    print("FAILED:", msg); sys.exit(1)
def figures(run):
    return [r for r in csv.DictReader(open(os.path.join(run, "figures.csv"))) if r["timing"] == "0"]
want_plain = figures(os.path.join(plain, "latest"))
if not want_plain: fail("the plain run has no figures")
crumb = "plugin 'evil_planner' (%s): plan" % library
want_failed = [
    {"variant": "segv", "status": "plugin_crashed", "cause": "plugin_crashed: %s: SIGSEGV" % crumb},
    {"variant": "abort", "status": "plugin_crashed", "cause": "plugin_crashed: %s: SIGABRT" % crumb},
    {"variant": "hang", "status": "wall_backstop",
     "cause": "wall_backstop: still running at the wall-clock backstop, in %s" % crumb}]
for run in (one, two):
    folder = os.path.realpath(os.path.join(run, "latest"))
    m = json.load(open(os.path.join(folder, "manifest.json")))
    if m["status"] != "partial": fail("replay manifest status %s" % m["status"])
    if m["failed"] != want_failed: fail("replay failed list %s" % m["failed"])
    got = figures(folder)
    if got != want_plain: fail("the plain variant's figures differ from a run of it alone")
    report = open(os.path.join(folder, "report.md")).read()
    if "## Variants that did not finish" not in report or "| hang | wall_backstop |" not in report:
        fail("report.md does not name the variants that did not finish")
print("replay: containment ok")
PY
grep -q "^flipper replay: variant segv: plugin_crashed: plugin 'evil_planner'" "$tmp/replay1.err" ||
  fail "replay does not name the crashed variant on stderr"

echo "== 4. the manifest says what ran: source tree now, libraries, plugin origins, plot versions"
mkdir -p "$tmp/shadow"
cp "$build/plugins/astar.so" "$build/plugins/astar.flipper.yaml" "$tmp/shadow/"
cat >"$tmp/shadow.yaml" <<EOF
name: shadow
plugin_paths: [$tmp/shadow]
worlds:
  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $data/maze-tasks.yaml}}
planners:
  - {plugin: astar}
EOF
"$flipper" bench planners --experiment "$tmp/shadow.yaml" --out "$tmp/shadow-runs" --jobs 1 \
  >/dev/null 2>"$tmp/shadow.err" || fail "the shadowing run failed"
grep -qxF "flipper bench planners: note: plugin 'astar' ($(readlink -f "$tmp/shadow/astar.so")) shadows $(readlink -f "$build/plugins/astar.so")" \
  "$tmp/shadow.err" || fail "no note of the shadowing astar: $(cat "$tmp/shadow.err")"
# Independent oracles: git now, pkg-config, the Python that draws plots.
commit=$(git -C "$src" rev-parse HEAD 2>/dev/null || echo unknown)
if [[ $commit == unknown ]]; then
  dirty=unknown
elif [[ -z $(git -C "$src" status --porcelain --untracked-files=no) ]]; then
  dirty=no
else
  dirty=yes
fi
versions=""
for m in ompl fcl octomap eigen3 sqlite3; do versions+="$m=$(pkg-config --modversion $m) "; done
python=$(/usr/bin/python3 -c 'import sys, matplotlib; print(sys.version.split()[0], matplotlib.__version__)' \
  2>/dev/null || echo none)
python3 - "$tmp/shadow-runs/latest" "$commit" "$dirty" "$versions" "$python" \
  "$(readlink -f "$build/plugins/astar.so")" "$tmp/shadow/astar.so" <<'PY'
import json, os, sys
run, commit, dirty, versions, python, intree, shadow = sys.argv[1:8]
def fail(msg):
    print("FAILED:", msg); sys.exit(1)
m = json.load(open(os.path.join(run, "manifest.json")))
src = m["source"]
if (src["commit"], src["dirty"]) != (commit, dirty): fail("source %s, git says %s %s" % (src, commit, dirty))
libs = m["build"]["libraries"]
names = {"ompl": "ompl", "fcl": "fcl", "octomap": "octomap", "eigen3": "eigen", "sqlite3": "sqlite"}
for pair in versions.split():
    pkg, version = pair.split("=")
    if libs[names[pkg]] != version: fail("%s %s, pkg-config says %s" % (pkg, libs[names[pkg]], version))
if not libs["compiler"].startswith(("GNU ", "Clang ")): fail("compiler %s" % libs["compiler"])
planner = [p for p in m["cells"][0]["plugins"] if p["section"] == "planner"][0]
if planner["file"] != os.path.realpath(shadow): fail("astar loaded from %s" % planner["file"])
if planner["origin"]["in_tree"] or planner["origin"]["shadows"] != [intree]:
    fail("the shadowing astar is not flagged: %s" % planner["origin"])
world = [p for p in m["cells"][0]["plugins"] if p["section"] == "world"][0]
if world["origin"] != {"dir": os.path.dirname(intree), "in_tree": True, "shadows": []}:
    fail("grid2d origin %s" % world["origin"])
if python != "none":
    if m["plots"]["status"] != "drawn": fail("plots %s" % m["plots"])
    v = m["plots"]["versions"]
    if "%s %s" % (v["python_version"], v["matplotlib"]) != python:
        fail("plot versions %s, not %s" % (v, python))
print("manifest: ok")
PY

echo "== 5. an interrupted run resumes in its own folder"
cp "$data/maze-tasks.yaml" "$tmp/tasks.yaml"
cat >"$tmp/resume.yaml" <<EOF
name: resume
plugin_paths: [$evil]
kill_after_s: 2
worlds:
  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $tmp/tasks.yaml}}
planners:
  - {plugin: astar}
  - {name: hang, plugin: evil_planner, params: {mode: hang, on_call: 2}}
  - {name: good, plugin: evil_planner, params: {mode: ok}}
EOF
setsid "$flipper" bench planners --experiment "$tmp/resume.yaml" --out "$tmp/resume" --jobs 1 \
  --no-plots >/dev/null 2>&1 &
pid=$!
# Interrupt it (the command and its cells) while its `hang` cell hangs on its second task.
for _ in $(seq 1 300); do
  [[ $(cat "$tmp"/resume/resume-*/cells/1.csv 2>/dev/null | wc -l) -ge 1 ]] && break
  sleep 0.1
done
kill -KILL -- "-$pid"
wait "$pid" 2>/dev/null || true
run=$(echo "$tmp"/resume/resume-*)
[[ -d $run/cells && ! -e $tmp/resume/latest ]] || fail "the interrupted run: no cells, or latest set"
grep -q '"status": "running"' "$run/manifest.json" || fail "the interrupted run's manifest is not running"
printf 'maze,astar,cut short' >>"$run/cells/0.csv"  # a row cut by the interruption
echo "# changed" >>"$tmp/tasks.yaml"
status=0
"$flipper" bench planners resume "$run" --no-plots >"$tmp/resume.out" 2>&1 || status=$?
[[ $status == 2 ]] && grep -q "tasks maze '$tmp/tasks.yaml' changed since the run started" "$tmp/resume.out" ||
  fail "resume with a changed task file: exit $status, $(cat "$tmp/resume.out")"
cp "$data/maze-tasks.yaml" "$tmp/tasks.yaml"
status=0
"$flipper" bench planners resume "$run" --jobs 2 --no-plots >/dev/null 2>&1 || status=$?
[[ $status == 1 ]] || fail "resume exited $status, not 1 (two tasks lost)"
[[ $(readlink "$tmp/resume/latest") == "$(basename "$run")" ]] || fail "latest not moved after resume"
python3 - "$run" "$tmp/bench1" <<'PY'
import csv, json, os, sys
run, clean = sys.argv[1], sys.argv[2]
def fail(msg):
    print("FAILED:", msg); sys.exit(1)
keep = ("planner", "task", "status", "success", "length", "cause")
rows = [tuple(r[k] for k in keep) for r in csv.DictReader(open(os.path.join(run, "runs.csv")))]
latest = os.path.join(clean, "latest")
ref = [tuple(r[k] for k in keep) for r in csv.DictReader(open(os.path.join(latest, "runs.csv")))
       if r["planner"] in ("astar", "good")]
# astar and good as in an uninterrupted run; `hang` by hand: corner done before the
# interruption, then a new process from `around` (its count starts again): around ok, back hangs,
# pocket ok (new process), cut_off hangs.
hang = [r for r in rows if r[0] == "hang"]
if [r[:3] for r in hang] != [("hang", "corner", "found"), ("hang", "around", "found"),
                             ("hang", "back", "wall_backstop"), ("hang", "pocket", "found"),
                             ("hang", "cut_off", "wall_backstop")]:
    fail("hang rows after resume: %s" % hang)
if [r for r in rows if r[0] != "hang"] != ref: fail("astar/good rows after resume differ")
m = json.load(open(os.path.join(run, "manifest.json")))
if m["status"] != "partial" or [(f["task"], f["status"]) for f in m["failed"]] != [
        ("back", "wall_backstop"), ("cut_off", "wall_backstop")]:
    fail("resumed manifest %s %s" % (m["status"], m["failed"]))
if os.path.exists(os.path.join(run, "cells")): fail("cells/ left behind")
print("resume: ok")
PY

echo "== 6. runs list|show, bench planners compare and check"
"$flipper" runs list "$tmp/bench1" >"$tmp/list.out"
cat "$tmp/list.out"
grep -q "^| bench-[0-9-]* (latest) | planner-benchmark | partial | .* | containment | 5 | " "$tmp/list.out" ||
  fail "runs list: the finished run"
grep -q "^| bench-[0-9-]* | planner-benchmark | running | .* | containment | 0 | " "$tmp/list.out" ||
  fail "runs list: the killed run"
grep -q "^2 run(s) in " "$tmp/list.out" || fail "runs list: count"
"$flipper" runs show "$tmp/bench1/latest" >"$tmp/show.out"
grep -q "^status: partial$" "$tmp/show.out" && grep -q "^lost: 5$" "$tmp/show.out" &&
  grep -q "^  segv on maze, task around: plugin_crashed: plugin 'evil_planner'" "$tmp/show.out" ||
  fail "runs show: $(cat "$tmp/show.out")"
status=0
"$flipper" runs show "$tmp/bench1" >/dev/null 2>&1 || status=$?
[[ $status == 2 ]] || fail "runs show of a parent exited $status, not 2"
"$flipper" bench planners compare "$tmp/bench1/latest" "$tmp/bench2/latest" >"$tmp/cmp.out" ||
  fail "compare of two runs of one experiment failed"
grep -q "^0 of [1-9][0-9]* figures differ" "$tmp/cmp.out" || fail "compare: $(tail -2 "$tmp/cmp.out")"
status=0
"$flipper" bench planners compare "$tmp/bench1/latest" "$tmp/replay1/latest" >"$tmp/cmp.out" 2>&1 ||
  status=$?
[[ $status == 1 ]] && grep -q "^Nothing compared" "$tmp/cmp.out" || fail "compare of unrelated runs: $status"

"$flipper" bench planners check "$tmp/shadow-runs/latest" --jobs 2 >"$tmp/check.out" ||
  fail "check of an unchanged run: $(cat "$tmp/check.out")"
grep -q "^0 of [1-9][0-9]* figures differ" "$tmp/check.out" || fail "check: $(tail -2 "$tmp/check.out")"
sed -i 's/^"world=maze,planner=astar",ours,all,solved,5,/"world=maze,planner=astar",ours,all,solved,4,/' \
  "$tmp/shadow-runs/latest/figures.csv"
status=0
"$flipper" bench planners check "$tmp/shadow-runs/latest" >"$tmp/check.out" || status=$?
[[ $status == 1 ]] && grep -q "^| ours / all / solved (plans) | 4 | 5 | +1 |" "$tmp/check.out" &&
  grep -q "^1 of [1-9][0-9]* figures differ" "$tmp/check.out" || fail "check of a changed figure: $status"

echo "== 7. --jobs 0 is refused"
for cmd in "bench planners --experiment $tmp/bench.yaml" "replay --experiment $tmp/plain.yaml"; do
  status=0
  $flipper $cmd --out "$tmp/zero" --jobs 0 >"$tmp/zero.out" 2>&1 || status=$?
  [[ $status == 2 ]] || fail "$cmd --jobs 0 exited $status, not 2"
  grep -q "\--jobs must be at least 1 (got 0)" "$tmp/zero.out" || fail "no --jobs message"
done
[[ ! -e $tmp/zero ]] || fail "--jobs 0 made a run folder"
echo "ok"
