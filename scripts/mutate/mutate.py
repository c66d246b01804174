#!/usr/bin/env python3
"""A mutation sample, one textual mutation at a time (docs/testing.md, "Tests that can fail").

Kept out of CI: it rebuilds and reruns tests once per mutant. Usage, from the repository root with
a configured Release tree in build/:

    python3 scripts/mutate/mutate.py [--list scripts/mutate/mutants.txt] [--only ID[,ID...]]
                                     [--build build] [--jobs 2]

Each mutant names a file, a snippet that must occur there exactly once, its replacement, the
targets to rebuild and a ctest regex for the tests that should catch it. For each: apply, build
(a build failure is "stillborn": not counted), run the tests, restore the file (always, even on
Ctrl-C), report caught (a test failed) or SURVIVED. The list format (mutants.txt):

    ## ID: one line saying which behaviour the mutant removes
    file: apps/studio/src/api.cpp
    targets: flipper test_studio_http
    tests: ^test_studio_http\\.the eleventh login
    --- original
    <lines>
    +++ mutant
    <lines>
    (a blank line or the next ## ends the mutant)
"""
import argparse
import os
import subprocess
import sys
import time


def parse(path):
    mutants, cur, mode = [], None, None
    for raw in open(path, encoding="utf-8").read().split("\n"):
        if raw.startswith("## "):
            if cur:
                mutants.append(cur)
            ident, _, why = raw[3:].partition(":")
            cur = {"id": ident.strip(), "why": why.strip(), "original": [], "mutant": []}
            mode = None
        elif cur is None or raw.startswith("#"):
            continue
        elif raw == "--- original":
            mode = "original"
        elif raw == "+++ mutant":
            mode = "mutant"
        elif mode and raw != "":
            cur[mode].append(raw)
        elif mode and raw == "":
            mode = None
        elif ":" in raw and mode is None:
            key, _, value = raw.partition(":")
            cur[key.strip()] = value.strip()
    if cur:
        mutants.append(cur)
    for m in mutants:
        m["original"] = "\n".join(m["original"])
        m["mutant"] = "\n".join(m["mutant"])
        for key in ("file", "targets", "tests"):
            if key not in m:
                sys.exit(f"mutant {m['id']}: no '{key}:' line")
    return mutants


def run(cmd, log):
    with open(log, "a", encoding="utf-8") as out:
        out.write(f"\n$ {' '.join(cmd)}\n")
        out.flush()
        return subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--list", default="scripts/mutate/mutants.txt")
    ap.add_argument("--only", default="")
    ap.add_argument("--build", default="build")
    ap.add_argument("--jobs", default="2")
    ap.add_argument("--log", default="build/mutate.log")
    args = ap.parse_args()
    mutants = parse(args.list)
    if args.only:
        wanted = set(args.only.split(","))
        mutants = [m for m in mutants if m["id"] in wanted]
    results = []
    for m in mutants:
        text = open(m["file"], encoding="utf-8").read()
        count = text.count(m["original"])
        if count != 1:
            results.append((m["id"], f"NOT APPLIED (snippet found {count} times)", 0.0))
            print(results[-1], flush=True)
            continue
        start = time.time()
        try:
            with open(m["file"], "w", encoding="utf-8") as f:
                f.write(text.replace(m["original"], m["mutant"]))
            built = run(["cmake", "--build", args.build, "-j", args.jobs, "--target"]
                        + m["targets"].split(), args.log) == 0
            if not built:
                verdict = "stillborn (does not build)"
            else:
                failed = run(["ctest", "--test-dir", args.build, "--no-tests=error",
                              "-j", args.jobs, "-R", m["tests"]], args.log) != 0
                verdict = "caught" if failed else "SURVIVED"
        finally:
            with open(m["file"], "w", encoding="utf-8") as f:
                f.write(text)
        results.append((m["id"], verdict, time.time() - start))
        print(f"{m['id']}: {verdict} ({results[-1][2]:.0f} s) - {m['why']}", flush=True)
    counted = [r for r in results if r[1] in ("caught", "SURVIVED")]
    caught = sum(1 for r in counted if r[1] == "caught")
    print(f"\ncaught {caught} / {len(counted)} "
          f"({len(results) - len(counted)} not counted: not applied or stillborn)")
    for r in results:
        if r[1] != "caught":
            print(f"  {r[0]}: {r[1]}")
    # The tree is rebuilt from the restored sources, so what is left in build/ is the real code.
    targets = sorted({t for m in mutants for t in m["targets"].split()})
    if targets:
        run(["cmake", "--build", args.build, "-j", args.jobs, "--target"] + targets, args.log)
    return 0 if caught == len(counted) else 1


if __name__ == "__main__":
    sys.exit(main())
