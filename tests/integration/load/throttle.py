#!/usr/bin/env python3
"""Runs a command starved to a fixed share of the CPU, without burning CPU to starve it.

Usage: throttle.py [--report FILE] SHARE_PERCENT COMMAND [ARG...]

The command runs in a process group of its own; every 100 ms period the group is continued
(SIGCONT) for SHARE_PERCENT of the period and stopped (SIGSTOP) for the rest (longer when this
script woke late, so that the share holds on a busy machine), so its wall time is
about 100 / SHARE_PERCENT times its CPU time, like a process at `nice 19` beside a busy loop (which
got 0.2-1.4 % of a core on this project's 2-core machine, docs/planners.md §2), but the CPU such
a loop would burn stays free for other work, and the share does not depend on what else runs.
The loaded phase of under_load.sh uses it; its exit status is the command's (128 + N for a
signal N). SIGTERM and SIGINT (timeout(1), ctest) are passed on to the group. --report FILE
appends a line "WALL_S CPU_S" for the command (its CPU: user + sys of it and the children it
waited for, not this script's own start-up), so that a caller can check the share it got.
"""
import os
import resource
import signal
import subprocess
import sys
import time

PERIOD_S = 0.1


def main() -> int:
    args = sys.argv[1:]
    report = None
    if len(args) >= 2 and args[0] == "--report":
        report, args = args[1], args[2:]
    if len(args) < 2:
        print("usage: throttle.py [--report FILE] SHARE_PERCENT COMMAND [ARG...]", file=sys.stderr)
        return 2
    try:
        share = float(args[0])
    except ValueError:
        share = -1.0
    if not 0.0 < share <= 100.0:
        print(f"throttle.py: SHARE_PERCENT must be in (0, 100], not {args[0]!r}", file=sys.stderr)
        return 2
    run_s = PERIOD_S * share / 100.0
    stop_per_run = (100.0 - share) / share

    started = time.monotonic()
    # A process group of its own in this session: should this script die (even by SIGKILL)
    # while the group is stopped, the group becomes orphaned and the kernel sends it SIGHUP and
    # SIGCONT, so no stopped command is left behind.
    child = subprocess.Popen(args[1:], process_group=0)
    group = child.pid

    def signal_group(sig: int) -> None:
        try:
            os.killpg(group, sig)
        except ProcessLookupError:
            pass

    def pass_on(signum: int, _frame: object) -> None:
        signal_group(signum)
        signal_group(signal.SIGCONT)

    signal.signal(signal.SIGTERM, pass_on)
    signal.signal(signal.SIGINT, pass_on)
    try:
        while child.poll() is None:
            ran_from = time.monotonic()
            time.sleep(run_s)
            if stop_per_run <= 0.0:
                continue
            signal_group(signal.SIGSTOP)
            # Stopped for as long as the share asks given how long the group really ran (this
            # script may wake late on a busy machine), so the share holds under load too.
            time.sleep((time.monotonic() - ran_from) * stop_per_run)
            signal_group(signal.SIGCONT)
    finally:
        signal_group(signal.SIGCONT)
    code = child.wait()
    if report is not None:
        used = resource.getrusage(resource.RUSAGE_CHILDREN)
        with open(report, "a", encoding="utf-8") as out:
            out.write(f"{time.monotonic() - started:.3f} {used.ru_utime + used.ru_stime:.3f}\n")
    return 128 - code if code < 0 else code


if __name__ == "__main__":
    sys.exit(main())
