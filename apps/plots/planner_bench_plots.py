"""Plots of a planner benchmark run (`flipper bench planners`, docs/planners.md §5).

Reads the run's figures.csv and variants.csv (one variant per world × planner × seed, its
condition the world × planner) and draws `planners` (PDF, SVG, .plotdata.json): per planner and
world the success rate, the path length relative to the oracle's shortest, the turns and the
plan CPU time (median per seed; µs where small, a log axis where planners differ by orders of
magnitude), each the mean over the seeds with its 95 % confidence interval as error bars, read
from the run's intervals.csv (Wilson for success, Student's t over the seeds for the rest;
docs/planners.md §5 "Intervals"); a run without intervals.csv (older) gets the seeds' standard
deviation.
Usage: planner_bench_plots.py RUN_DIR
"""

import csv
import os
import sys

import flipper_plot as fp


def parse_condition(condition):
    parts = dict(p.split("=", 1) for p in condition.split(","))
    return parts["world"], parts["planner"]


def read_intervals(run_dir):
    """intervals.csv as {(condition, metric): (low, high) or None}, or None when absent."""
    path = os.path.join(run_dir, "intervals.csv")
    if not os.path.exists(path):
        return None
    with open(path, newline="", encoding="utf-8") as f:
        return {(r["condition"], r["metric"]):
                (float(r["low"]), float(r["high"])) if r["low"] != "" else None
                for r in csv.DictReader(f)}


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: planner_bench_plots.py RUN_DIR\n")
        return 2
    run_dir = sys.argv[1]
    figures = fp.Figures(fp.read_figures(run_dir))
    conds = fp.conditions(fp.read_variants(run_dir))
    worlds, planners, cells = [], [], {}
    for condition, names in conds:
        world, planner = parse_condition(condition)
        if world not in worlds:
            worlds.append(world)
        if planner not in planners:
            planners.append(planner)
        cells[(world, planner)] = names
    seeded = any(len(names) > 1 for _, names in conds)
    intervals = read_intervals(run_dir)
    condition_of = {parse_condition(c): c for c, _ in conds}

    def series(metric, scale=1.0):
        out = []
        for world in worlds:
            values, below, above = [], [], []
            for planner in planners:
                names = cells.get((world, planner))
                if not names:
                    values.append(0.0)
                    below.append(0.0)
                    above.append(0.0)
                    continue
                mean, sd, _, _ = fp.over_seeds(
                    [figures.get(n, "ours", "all", metric) * scale for n in names])
                values.append(mean)
                if intervals is None:
                    below.append(sd)
                    above.append(sd)
                    continue
                ci = intervals.get((condition_of[(world, planner)], metric))
                below.append(max(0.0, mean - ci[0] * scale) if ci else 0.0)
                above.append(max(0.0, ci[1] * scale - mean) if ci else 0.0)
            bars = seeded or (intervals is not None and metric == "success")
            out.append({"label": world, "values": values,
                        "errors": [below, above] if bars else None})
        return out

    cpu_ms = [figures.get(n, "ours", "all", "cpu_us_median") / 1000.0
              for _, names in conds for n in names]
    unit, scale = fp.time_unit(cpu_ms)
    what = "sd" if intervals is None else "95 % CI"
    note = " (mean over seeds, error bars: %s)" % what if seeded else ""
    # Success has an interval with one seed too: its Wilson interval over the tasks.
    success_note = note if note or intervals is None else " (error bars: 95 % Wilson)"
    spec = [
        ("Success rate" + success_note, "success", "%", "% of tasks", 1.0, False),
        ("Path length / shortest (oracle)" + note, "length_ratio_mean", "", "ratio (mean)", 1.0,
         False),
        ("Turns per path" + note, "turns_mean", "turns", "turns (mean)", 1.0, False),
        ("Plan CPU time per task, median (measured)" + note, "cpu_us_median", unit, unit,
         scale / 1000.0, True),
    ]
    fig, axes = fp.new_figure(len(spec))
    data = []
    for ax, (title, metric, u, ylabel, sc, timing) in zip(axes, spec):
        s = series(metric, sc)
        panel = fp.bar_panel(ax, title, planners, s, u, ylabel, timing=timing)
        positive = [v for x in s for v in x["values"] if v > 0]
        panel["log"] = False
        if timing and positive and max(positive) / min(positive) > 100:
            ax.set_yscale("log")
            ax.set_ylim(min(positive) / 2, max(positive) * 4)
            ax.set_title(title + " (log axis)")
            panel.update({"log": True, "title": ax.get_title(),
                          "ylim": [min(positive) / 2, max(positive) * 4], "zoomed": False})
        data.append(panel)
    fp.save(fig, axes, os.path.join(run_dir, "planners"), "planners", data)
    print("plots: planners (PDF, SVG and .plotdata.json) in %s" % run_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
