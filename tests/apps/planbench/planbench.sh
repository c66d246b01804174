#!/usr/bin/env bash
# `flipper bench planners` end to end (docs/planners.md §5):
# 1. the out-of-tree example planner bfs_example, built against the installed SDK (as
#    tests/kernel/out_of_tree.sh builds it), benchmarked beside astar and ompl in one run, on a
#    maze with hand-drawn tasks; lengths and turns checked against an oracle computed here
#    (breadth-first search in Python, neighbours in the grid's tie order right, left, up, down),
#    and two tasks against hand-counted figures;
# 2. the same run with --jobs 1 and --jobs 2: every deterministic column of runs.csv, tasks.csv
#    and figures.csv equal;
# 3. the run folder: manifest (bfs_example's SHA-256), report, plots whose data are figures.csv's;
# 4. load errors (a missing plugin, a plugin of another kind, a bad param, a missing world, a bad
#    task file) exit 2 with `flipper bench planners: [code] message`, never `terminate`, and
#    leave no run folder; --help exits 0.
# Usage: planbench.sh <source dir> <build dir>
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

echo "== 1. build bfs_example against the installed SDK"
prefix=$tmp/prefix
cmake --install "$build" --component sdk --prefix "$prefix" >/dev/null
cp -r "$prefix/share/flipper/examples/out-of-tree-planner" "$tmp/example"
cmake -S "$tmp/example" -B "$tmp/example-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >/dev/null
cmake --build "$tmp/example-build" -j2 >/dev/null
plugins=$tmp/example-build/plugins
test -f "$plugins/bfs_example.so" || fail "bfs_example.so was not built"

experiment() {  # experiment FILE [planner lines...]
  local file=$1
  shift
  {
    echo "name: out-of-tree vs in-tree"
    echo "plugin_paths: [$plugins]"
    echo "seeds: [1, 2]"
    echo "worlds:"
    echo "  - {name: maze, plugin: grid2d, file: $data/maze.json, tasks: {file: $data/maze-tasks.yaml}}"
    echo "planners:"
    for p in "$@"; do echo "  - $p"; done
  } >"$file"
}
experiment "$tmp/bench.yaml" "{plugin: bfs_example}" "{plugin: astar}" \
  "{name: rrtconnect, plugin: ompl, params: {planner: rrtconnect}}"

echo "== 2. one run with --jobs 1, one with --jobs 2"
"$flipper" bench planners --experiment "$tmp/bench.yaml" --out "$tmp/runs1" --jobs 1 >"$tmp/out1"
"$flipper" bench planners --experiment "$tmp/bench.yaml" --out "$tmp/runs2" --jobs 2 \
  --print results >"$tmp/table2"
cat "$tmp/out1" "$tmp/table2"
run1=$(sed -n 's/^run: //p' "$tmp/out1")
run2=$(readlink -f "$tmp/runs2/latest")
[[ -d $run1 && -d $run2 && $run1 != "$run2" ]] || fail "no run folders"

python3 - "$run1" "$run2" "$data" <<'PY'
import csv, json, os, sys
from collections import deque
run1, run2, data = sys.argv[1:4]
def fail(msg):
    print("FAILED:", msg); sys.exit(1)

# The oracle: the maze read from its JSON, breadth-first search in the tie order.
world = json.load(open(os.path.join(data, "maze.json")))
lo, hi = world["bounds"]["min"], world["bounds"]["max"]
walls = {tuple(w) for w in world["walls"]}
free = lambda c: lo[0] <= c[0] <= hi[0] and lo[1] <= c[1] <= hi[1] and c not in walls
order = [(1, 0), (-1, 0), (0, 1), (0, -1)]  # right, left, up, down
def bfs(s, g):
    parent, q = {s: None}, deque([s])
    while q:
        c = q.popleft()
        if c == g:
            path = []
            while c != s:
                path.append(c); c = parent[c]
            return path[::-1]
        for d in order:
            n = (c[0] + d[0], c[1] + d[1])
            if free(n) and n not in parent:
                parent[n] = c; q.append(n)
    return None
def turns(s, path):
    steps = [(b[0] - a[0], b[1] - a[1]) for a, b in zip([s] + path, path)]
    return sum(1 for a, b in zip(steps, steps[1:]) if a != b)
cell = lambda text: tuple(int(v) for v in text.strip("[]").split(","))

rows = list(csv.DictReader(open(os.path.join(run1, "runs.csv"))))
by = {}
for r in rows:
    by.setdefault(r["planner"], []).append(r)
if sorted(by) != ["astar", "bfs_example", "rrtconnect"]:
    fail("planners in runs.csv: %s" % sorted(by))
# astar and bfs_example declare no seed: one run per task; ompl: one per task and seed.
if [len(by[p]) for p in ("bfs_example", "astar", "rrtconnect")] != [5, 5, 10]:
    fail("rows per planner: %s" % {p: len(v) for p, v in by.items()})
hand = {"corner": (4, 1), "pocket": (2, 0)}  # counted by hand on the maze drawing
for r in rows:
    s, g = cell(r["start"]), cell(r["goal"])
    path = bfs(s, g)
    if path is None:
        if r["task"] != "cut_off": fail("the oracle cannot reach %s" % r["task"])
        if (r["status"], r["success"], r["shortest"], r["length"]) != ("no_path", "1", "", ""):
            fail("unreachable task: %s" % r)
        continue
    if r["shortest"] != str(len(path)): fail("shortest %s, oracle %d: %s" % (r["shortest"], len(path), r))
    if r["task"] in hand and hand[r["task"]] != (len(path), turns(s, path)):
        fail("the oracle disagrees with the hand count on %s" % r["task"])
    if r["status"] != "found" or r["success"] != "1": fail("not solved: %s" % r)
    if r["planner"] in ("bfs_example", "astar"):  # optimal: the breadth-first path itself
        want = (str(len(path)), "1", str(turns(s, path)))
        if (r["length"], r["length_ratio"], r["turns"]) != want:
            fail("%s on %s: length, ratio, turns %s, oracle %s" %
                 (r["planner"], r["task"], (r["length"], r["length_ratio"], r["turns"]), want))
    elif int(r["length"]) < len(path) or float(r["length_ratio"]) != int(r["length"]) / len(path):
        fail("ompl shorter than the shortest, or a wrong ratio: %s" % r)
    if float(r["cpu_us"]) <= 0 or not r["peak_rss_kib"]: fail("no measurement: %s" % r)

# --jobs 1 and --jobs 2: the same deterministic columns, the same tasks and figures.
measured = {"cpu_us", "wall_us", "peak_rss_kib", "memory_kib"}
def deterministic(run, name, drop):
    out = []
    for r in csv.DictReader(open(os.path.join(run, name))):
        if name == "figures.csv" and r["timing"] == "1": continue
        out.append({k: v for k, v in r.items() if k not in drop})
    return out
for name, drop in (("runs.csv", measured), ("tasks.csv", set()), ("figures.csv", set())):
    a, b = deterministic(run1, name, drop), deterministic(run2, name, drop)
    if not a or a != b: fail("%s differs between --jobs 1 and --jobs 2" % name)

# The manifest names the out-of-tree plugin with its file's checksum.
import hashlib
m = json.load(open(os.path.join(run1, "manifest.json")))
bfs_plugins = [p for c in m["cells"] for p in c["plugins"] if p["name"] == "bfs_example"]
if not bfs_plugins: fail("the manifest does not name bfs_example")
so = bfs_plugins[0]["file"]
if bfs_plugins[0]["sha256"] != hashlib.sha256(open(so, "rb").read()).hexdigest():
    fail("bfs_example's checksum in the manifest differs from the file's")
if m["kind"] != "planner-benchmark" or m["jobs"] != 1: fail("manifest kind/jobs")
# Each ompl cell ran with its own seed; the unseeded planners with none.
seeds = [(c["planner"], c["seed"], [p["params"].get("seed") for p in c["plugins"] if p["section"] == "planner"][0])
         for c in m["cells"]]
if seeds != [("bfs_example", "", None), ("astar", "", None), ("rrtconnect", "1", "1"), ("rrtconnect", "2", "2")]:
    fail("cells and their planner seeds: %s" % seeds)

# The figures: success 100 % everywhere (cut_off counts as solved by no_path).
figs = {(r["variant"], r["metric"]): float(r["value"]) for r in csv.DictReader(open(os.path.join(run1, "figures.csv")))}
for v in ("world=maze,planner=bfs_example", "world=maze,planner=astar",
          "world=maze,planner=rrtconnect,seed=1", "world=maze,planner=rrtconnect,seed=2"):
    if figs.get((v, "success")) != 100.0 or figs.get((v, "tasks")) != 5.0:
        fail("figures of %s" % v)
    if "rrtconnect" not in v and figs[(v, "length_ratio_mean")] != 1.0: fail("ratio of %s" % v)

# The plots show figures.csv's values (when this Python has matplotlib).
plot = os.path.join(run1, "planners.plotdata.json")
if os.path.exists(plot):
    p = json.load(open(plot))
    panel = p["panels"][0]
    if panel["categories"] != ["bfs_example", "astar", "rrtconnect"] or panel["unit"] != "%":
        fail("success panel: %s" % panel["categories"])
    if panel["series"][0]["values"] != [100.0, 100.0, 100.0]: fail("success values")
    ratio = p["panels"][1]["series"][0]["values"]
    want = (figs[("world=maze,planner=rrtconnect,seed=1", "length_ratio_mean")] +
            figs[("world=maze,planner=rrtconnect,seed=2", "length_ratio_mean")]) / 2
    if ratio[:2] != [1.0, 1.0] or abs(ratio[2] - want) > 1e-12: fail("ratio panel %s" % ratio)
    # Error bars: 95 % intervals from intervals.csv, recomputed here: success is Wilson's for
    # 5 of 5 (unseeded) and 10 of 10 plans (z = NormalDist's 97.5 % point); rrtconnect's ratio
    # is t over its two seeds' figures (t(0.975; 1) = tan(0.475 π)), the low end cut at 1.
    import math
    from statistics import NormalDist
    z = NormalDist().inv_cdf(0.975)
    def wilson_low(k, n):
        p_ = k / n
        return ((p_ + z * z / (2 * n)) - z * math.sqrt(p_ * (1 - p_) / n + z * z / (4 * n * n))) / (1 + z * z / n)
    errors = panel["series"][0]["errors"]
    want_below = [100 * (1 - wilson_low(5, 5))] * 2 + [100 * (1 - wilson_low(10, 10))]
    if any(abs(a - b) > 1e-9 for a, b in zip(errors[0], want_below)) or errors[1] != [0.0] * 3:
        fail("success error bars %s, want below %s" % (errors, want_below))
    r1 = figs[("world=maze,planner=rrtconnect,seed=1", "length_ratio_mean")]
    r2 = figs[("world=maze,planner=rrtconnect,seed=2", "length_ratio_mean")]
    half = math.tan(0.475 * math.pi) * abs(r1 - r2) / math.sqrt(2) / math.sqrt(2)
    ratio_errors = p["panels"][1]["series"][0]["errors"]
    if ratio_errors[0][:2] != [0.0, 0.0] or ratio_errors[1][:2] != [0.0, 0.0]:
        fail("unseeded ratio error bars %s" % ratio_errors)
    if (abs(ratio_errors[1][2] - half) > 1e-9 or
            abs(ratio_errors[0][2] - (want - max(1.0, want - half))) > 1e-9):
        fail("rrtconnect ratio error bars %s, want +%s" % (ratio_errors, half))
    if "95 % CI" not in p["panels"][1]["title"]: fail("ratio panel title %s" % p["panels"][1]["title"])
    for ext in ("pdf", "svg"):
        if not os.path.getsize(os.path.join(run1, "planners." + ext)): fail("no planners." + ext)
    print("plots checked")
print("runs.csv, tasks.csv, figures.csv, manifest checked")
PY
grep -q "^| maze | bfs_example | – | 5 | 100.0 % (5) |" "$tmp/table2" || fail "--print results table"

echo "== 3. load errors exit 2 in the one format and leave no run folder"
refused() {  # refused CODE TEXT args...
  local code=$1 text=$2
  shift 2
  set +e
  "$flipper" bench planners "$@" --out "$tmp/refused" >"$tmp/err.out" 2>"$tmp/err"
  local status=$?
  set -e
  cat "$tmp/err"
  [[ $status == 2 ]] || fail "exit $status, not 2, for: $*"
  grep -q "^flipper bench planners: \[$code\] .*$text" "$tmp/err" || fail "message for: $*"
  ! grep -q "terminate" "$tmp/err" || fail "terminate"
  [[ ! -e $tmp/refused ]] || fail "a refused run left $tmp/refused"
}
experiment "$tmp/missing.yaml" "{plugin: no_such_planner}"
refused plugin_not_found "no_such_planner" --experiment "$tmp/missing.yaml"
experiment "$tmp/kind.yaml" "{plugin: grid2d}"
refused plugin_not_found "grid2d.* is a world plugin, not a planner plugin" --experiment "$tmp/kind.yaml"
experiment "$tmp/param.yaml" "{plugin: bfs_example, params: {max_expansion: 5}}"
refused bad_config "max_expansion" --experiment "$tmp/param.yaml"
experiment "$tmp/range.yaml" "{plugin: bfs_example, params: {max_expansions: -1}}"
refused bad_config "max_expansions" --experiment "$tmp/range.yaml"
# Without the plugin path, the out-of-tree plugin is not found; with --set it is.
sed '/^plugin_paths/d' "$tmp/bench.yaml" >"$tmp/nopath.yaml"
refused plugin_not_found "bfs_example" --experiment "$tmp/nopath.yaml"
"$flipper" bench planners --experiment "$tmp/nopath.yaml" --set "plugin_paths=[$plugins]" \
  --out "$tmp/setpath" --no-plots --print results | grep -q "^| maze | bfs_example " ||
  fail "--set plugin_paths=[DIR] did not find bfs_example"
sed "s|$data/maze.json|$tmp/none.json|" "$tmp/bench.yaml" >"$tmp/noworld.yaml"
refused bad_world "none.json" --experiment "$tmp/noworld.yaml"
printf 'tasks:\n  - {start: [1, 1], goal: [0, 0]}\n' >"$tmp/wall-task.yaml"
sed "s|$data/maze-tasks.yaml|$tmp/wall-task.yaml|" "$tmp/bench.yaml" >"$tmp/badtask.yaml"
refused bad_config "is not a free cell" --experiment "$tmp/badtask.yaml"
refused usage "--experiment" --jobs 2
refused bad_config "cannot read experiment" --experiment "$tmp/absent.yaml"
# Experiment and task files get a config's bounds: no device or FIFO, no alias bomb (100,000
# nodes once expanded; this one expands to a million in a few hundred bytes).
refused bad_config "is not a regular file" --experiment /dev/zero
printf 'a: &a [x,x,x,x,x,x,x,x,x,x]\n' >"$tmp/bomb.yaml"
prev=a
for n in b c d e f; do
  printf '%s: &%s [*%s,*%s,*%s,*%s,*%s,*%s,*%s,*%s,*%s,*%s]\n' $n $n $prev $prev $prev $prev \
    $prev $prev $prev $prev $prev $prev >>"$tmp/bomb.yaml"
  prev=$n
done
refused bad_config "more than 100000 YAML nodes" --experiment "$tmp/bomb.yaml"
sed "s|$data/maze-tasks.yaml|$tmp/bomb.yaml|" "$tmp/bench.yaml" >"$tmp/bombtasks.yaml"
refused bad_config "more than 100000 YAML nodes" --experiment "$tmp/bombtasks.yaml"
"$flipper" bench planners --help | grep -q "^Usage: .*bench planners" || fail "--help"
echo "planner benchmark OK"
