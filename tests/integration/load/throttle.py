#!/usr/bin/env python3
"""Runs a command starved to a fixed share of the CPU, without burning CPU to starve it.

Usage: throttle.py [--report FILE] SHARE_PERCENT COMMAND [ARG...]

The command runs in a process group of its own; every 100 ms period the group is continued
(SIGCONT) for SHARE_PERCENT of the period and stopped (SIGSTOP) for the rest (longer when this
script woke late, and until the command's CPU time so far, read from /proc, is at most
SHARE_PERCENT of the wall time so far: a command running on several cores at once, or one whose
run this script did not see end, still gets its share and no more), so its wall time is
about 100 / SHARE_PERCENT times its CPU time, like a process at `nice 19` beside a busy loop (which
got 0.2-1.4 % of a core on this project's 2-core machine, docs/planners.md §2), but the CPU such
a loop would burn stays free for other work, and the share does not depend on what else runs.
The loaded phase of under_load.sh uses it; its exit status is the command's (128 + N for a
signal N). SIGTERM and SIGINT (timeout(1), ctest) are passed on to the group. --report FILE
appends a line "WALL_S CPU_S" for the command (its CPU: user + sys of it and the children it
waited for, not this script's own start-up nor what a wrapper that started it, such as
pyenv's shim, waited for), so that a caller can check the share it got.
"""
import os
import resource
import signal
import subprocess
import sys
import time

PERIOD_S = 0.1
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    """The CPU time (user + sys of all its threads and of the children it waited for) of `pid`,
    0 once it is gone (/proc/PID/stat, proc(5): fields 14-17 in clock ticks)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return sum(int(f) for f in fields[11:15]) / CLOCK_TICKS


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

    # What this process's children used before the command: a `python3` that is a wrapper
    # script (pyenv's shim) waited for its own helpers before it exec'd this interpreter, and
    # RUSAGE_CHILDREN keeps their CPU across exec (0.27 s of it on this project's machines: a
    # report without this baseline said the starved commands got 5 % of a CPU).
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
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
        # The group may run from the moment it is continued until the moment it is stopped, so
        # both ends are read on this script's side of the signal: `ran_from` before SIGCONT (the
        # group started at Popen) and the run's end after SIGSTOP. A busy machine may keep this
        # script off the CPU right after it sends SIGCONT (the woken group preempts it) or
        # before it sends SIGSTOP; either delay counts as the group's run, so the stop that
        # follows is long enough and the share holds under load too.
        ran_from = started
        while child.poll() is None:
            time.sleep(run_s)
            if stop_per_run <= 0.0:
                continue
            signal_group(signal.SIGSTOP)
            stopped_at = time.monotonic()
            # The share by the clock, and by the CPU the command used (all its cores' time,
            # which a multi-threaded command spends faster than the clock runs).
            resume_at = max(stopped_at + (stopped_at - ran_from) * stop_per_run,
                            started + cpu_seconds(child.pid) * 100.0 / share)
            time.sleep(max(0.0, resume_at - stopped_at))
            ran_from = time.monotonic()
            signal_group(signal.SIGCONT)
    finally:
        signal_group(signal.SIGCONT)
    code = child.wait()
    if report is not None:
        used = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (used.ru_utime + used.ru_stime) - (before.ru_utime + before.ru_stime)
        with open(report, "a", encoding="utf-8") as out:
            out.write(f"{time.monotonic() - started:.3f} {cpu:.3f}\n")
    return 128 - code if code < 0 else code


if __name__ == "__main__":
    sys.exit(main())
