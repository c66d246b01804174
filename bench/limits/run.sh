#!/usr/bin/env bash
# Time and peak memory of `flipper session` on each hostile input of the bad-input table (tests/integration/limits), next to its target
# (answered within session.cpu_budget_ms (5 s of CPU: wall time on a quiet machine) + 1 s, peak RSS <= 100 MB unless noted). Inputs are made in
# a temp dir. Usage: bash bench/limits/run.sh [FLIPPER]
set -euo pipefail
flipper=$(realpath "${1:-build/bin/flipper}")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
def w(name, lines):
    with open(f"{d}/{name}.jsonl", "wb") as f:
        for l in lines:
            f.write((l if isinstance(l, bytes) else l.encode()) + b"\n")
q = lambda t: json.dumps({"op": "query", "text": t})
w("utf8", [b'{"op":"query","text":"\xff"}'])
w("e999", ['{"op":"query","text":"move left","k":1e999}'])
w("int400", ['{"op":"state","id":' + "9" * 400 + "}"])
w("deep_id", ['{"op":"state","id":' + "[" * 50000 + "1" + "]" * 50000 + "}"])
w("head_65535", [json.dumps({"op": "define", "head": " ".join(["zz"] * 65535), "body": ["move left"]})])
w("body_65535", [json.dumps({"op": "define", "head": "glorb", "body": [" ".join(["up"] * 65535)]})])
w("head_110k", [json.dumps({"op": "define", "head": "a " * 55000, "body": ["move left"]})])
w("braces_990", [q("{" * 990 + "move left" + "}" * 990)])
w("not_red_x30", [q("pick item not is red" + " and not is red" * 29)])
items = [{"x": 1, "y": 1, "color": "red", "shape": "circle"}] * 30000
json.dump({"bounds": {"min": [0, 0], "max": [3, 3]}, "robot": {"x": 1, "y": 1}, "items": items},
          open(f"{d}/many.json", "w"))
w("pick_30000", [json.dumps({"op": "world", "file": f"{d}/many.json"}), q("pick every item")])
w("foreach_3000", [json.dumps({"op": "world", "world": {"bounds": {"min": [0, 0], "max": [2999, 2999]},
                                                        "robot": {"x": 0, "y": 0}}}),
                   q("foreach point in world visit point")])
w("bounds_16382", ['{"op":"world","world":{"bounds":{"min":[0,0],"max":[16381,16381]},"robot":{"x":0,"y":0}}}'])
w("dev_zero", ['{"op":"world","file":"/dev/zero"}'])
w("fifo", [json.dumps({"op": "world", "file": f"{d}/fifo"})])
with open(f"{d}/line_68mb.jsonl", "w") as f:
    f.write('{"op":"query","text":"' + "a" * (68 << 20) + '"}\n')
PY
mkfifo "$dir/fifo"
printf '%-14s %9s %10s  %s\n' input wall_s peak_MB "target: wall <= CPU budget (5 s) + 1 s, peak <= 100 MB"
for name in utf8 e999 int400 deep_id head_65535 body_65535 head_110k braces_990 not_red_x30 \
  pick_30000 foreach_3000 bounds_16382 dev_zero fifo line_68mb; do
  extra=()
  [[ $name == foreach_3000 ]] && extra=(--set world.max_cells=9000000)
  [[ $name == braces_990 ]] && extra=(--set input.max_tokens=2000)  # reach the parser
  /usr/bin/time -f '%e %M' -o "$dir/time" timeout 60 "$flipper" session \
    --set lexicon.path=:memory: "${extra[@]}" <"$dir/$name.jsonl" >"$dir/out" 2>&1 || true
  read -r wall kb <"$dir/time"
  code=$(python3 -c 'import json,sys
for l in open(sys.argv[1]):
    a = json.loads(l)
    if not a["ok"]: print(a["error"]["code"]); break
    c = a.get("candidates") or []
    if c and c[0].get("error"): print("candidate:" + c[0]["error"]["code"]); break
else: print("ok")' "$dir/out" 2>/dev/null || echo crashed)
  awk -v n="$name" -v w="$wall" -v k="$kb" -v c="$code" 'BEGIN { printf "%-14s %9s %10.1f  %s\n", n, w, k / 1024, c }'
done
