"""The plots of a `flipper replay` run folder (docs/experiments.md §5).

Usage: replay_plots.py RUN_DIR

Reads RUN_DIR/figures.csv and RUN_DIR/variants.csv only. Writes, per variant into its folder,
tokens, induced_core, others_self and latency; with more than one variant, into RUN_DIR,
variants (status agreement, rank of the accepted program, tokens, induced/core commands) and
planner (success, path length, turns, plan CPU time). Each as .pdf, .svg and .plotdata.json.
With several seeds per condition the cross-variant plots show the mean over seeds with the
sample standard deviation as error bars.
"""

import os
import sys

import flipper_plot as fp


def variant_figures(run_dir, figures, v):
    name, folder = v["variant"], os.path.join(run_dir, v["directory"])
    get = lambda source, group, metric: figures.get(name, source, group, metric)
    drawn = 0

    fig, axes = fp.new_figure(1)
    panel = fp.bar_panel(
        axes[0], "Tokens per participant (task queries)", ["A", "B", "C"],
        [{"label": "successful (original)",
          "values": [get("original", g, "tokens_successful_mean") for g in "ABC"]},
         {"label": "successful (ours)",
          "values": [get("ours", g, "tokens_successful_mean") for g in "ABC"]},
         {"label": "all queries", "values": [get("ours", g, "tokens_all_mean") for g in "ABC"]}],
        "tokens", "tokens per participant (mean)")
    fp.save(fig, axes, os.path.join(folder, "tokens"), "tokens", [panel])
    drawn += 1

    def whiskered(source, metric, groups):
        means = [get(source, g, metric + "_mean") for g in groups]
        return {"values": means,
                "errors": [[m - get(source, g, metric + "_min") for m, g in zip(means, groups)],
                           [get(source, g, metric + "_max") - m for m, g in zip(means, groups)]]}

    fig, axes = fp.new_figure(1)
    series = []
    for source, label in (("original", "original"), ("ours", "ours")):
        induced, core = whiskered(source, "induced", "BC"), whiskered(source, "core", "BC")
        series.append({"label": label, "values": induced["values"] + core["values"],
                       "errors": [induced["errors"][0] + core["errors"][0],
                                  induced["errors"][1] + core["errors"][1]]})
    panel = fp.bar_panel(axes[0], "Induced vs core commands per participant "
                         "(bars: mean; whiskers: min–max over participants)",
                         ["induced B", "induced C", "core B", "core C"], series, "commands",
                         "commands per participant")
    fp.save(fig, axes, os.path.join(folder, "induced_core"), "induced_core", [panel])
    drawn += 1

    fig, axes = fp.new_figure(1)
    series = []
    for source in ("original", "ours"):
        others, own = whiskered(source, "by_others", "C"), whiskered(source, "by_self", "C")
        series.append({"label": source, "values": others["values"] + own["values"],
                       "errors": [others["errors"][0] + own["errors"][0],
                                  others["errors"][1] + own["errors"][1]]})
    panel = fp.bar_panel(axes[0], "Group C: induced commands using rules by others vs by self "
                         "(whiskers: min–max)", ["by others", "by self"], series, "commands",
                         "commands per participant")
    fp.save(fig, axes, os.path.join(folder, "others_self"), "others_self", [panel])
    drawn += 1

    # Latency: the occupied bins of the log-scale histogram; bin labels in µs below 1 ms.
    edges = figures.groups(name, "ours", "latency_histogram")
    counts = {s: [get(s, e, "latency_histogram") for e in edges] for s in ("original", "ours")}
    occupied = [i for i, e in enumerate(edges) if counts["original"][i] + counts["ours"][i] > 0]
    if occupied:
        keep = range(occupied[0], occupied[-1] + 1)
        labels = []
        for i in keep:
            ms = float(edges[i])
            labels.append(("%g µs" % round(ms * 1000, 1)) if ms < 1 else ("%g ms" % round(ms, 1)))
        fig, axes = fp.new_figure(1)
        panel = fp.bar_panel(
            axes[0], "Query latency, log-scale bins from the edge shown (different measures)",
            labels,
            [{"label": "original: logged server wall time",
              "values": [counts["original"][i] for i in keep]},
             {"label": "ours: in-process parse + plan (timing)",
              "values": [counts["ours"][i] for i in keep]}],
            "queries", "queries", timing=True, integer=True)
        fp.save(fig, axes, os.path.join(folder, "latency"), "latency", [panel])
        drawn += 1
    return drawn


def condition_series(figures, conds, source, group, metric, scale=1.0):
    """One value per condition (mean over its seeds) and its error bars (sd), scaled."""
    means, sds = [], []
    for _, names in conds:
        mean, sd, _, _ = fp.over_seeds([figures.get(n, source, group, metric) * scale
                                        for n in names])
        means.append(mean)
        sds.append(sd)
    seeded = any(len(names) > 1 for _, names in conds)
    return means, ([sds, sds] if seeded else None)


def cross_variant_figures(run_dir, figures, variants):
    conds = fp.conditions(variants)
    seeded = any(len(names) > 1 for _, names in conds)
    note = " (mean over seeds; error bars: sd)" if seeded else ""

    def by_condition(categories, metrics, scale=1.0):
        """Series per condition over categories [(source, group, metric)]."""
        out = []
        for label, names in conds:
            values, errors = [], [[], []]
            for source, group, metric in metrics:
                mean, sd, _, _ = fp.over_seeds(
                    [figures.get(n, source, group, metric) * scale for n in names])
                values.append(mean)
                errors[0].append(sd)
                errors[1].append(sd)
            out.append({"label": label, "values": values,
                        "errors": errors if seeded else None})
        return out

    panels_spec = [
        ("Status agreement with the original" + note, ["A", "B", "C", "all"],
         [("ours", g, "agreement") for g in ("A", "B", "C", "all")], "%", "% of queries"),
        ("Tokens of successful commands per participant" + note, ["A", "B", "C"],
         [("ours", g, "tokens_successful_mean") for g in "ABC"], "tokens", "tokens (mean)"),
        ("Induced vs core commands per participant" + note,
         ["induced B", "induced C", "core B", "core C"],
         [("ours", "B", "induced_mean"), ("ours", "C", "induced_mean"),
          ("ours", "B", "core_mean"), ("ours", "C", "core_mean")], "commands", "commands (mean)"),
    ]
    fig, axes = fp.new_figure(len(panels_spec) + 1)
    data = []
    for ax, (title, cats, metrics, unit, ylabel) in zip(axes, panels_spec):
        data.append(fp.bar_panel(ax, title, cats, by_condition(cats, metrics), unit, ylabel))
    # The accepted program's rank, as % of the matched accepts.
    series = []
    for label, names in conds:
        firsts, tops = [], []
        for n in names:
            matched = max(1.0, figures.get(n, "ours", "all", "accepts_matched"))
            firsts.append(100.0 * figures.get(n, "ours", "all", "accepted_first") / matched)
            tops.append(100.0 * figures.get(n, "ours", "all", "accepted_top3") / matched)
        (m1, s1, _, _), (m3, s3, _, _) = fp.over_seeds(firsts), fp.over_seeds(tops)
        series.append({"label": label, "values": [m1, m3],
                       "errors": [[s1, s3], [s1, s3]] if seeded else None})
    data.append(fp.bar_panel(axes[-1], "Rank of the accepted program" + note,
                             ["first", "among the first three"], series, "%",
                             "% of matched accepts"))
    fp.save(fig, axes, os.path.join(run_dir, "variants"), "variants", data)

    # The planner on the accepted programs.
    cpu = [figures.get(n, "ours", "all", "plan_cpu_p50") for _, names in conds for n in names]
    unit, scale = fp.time_unit(cpu)
    planner_spec = [
        ("Planner success on the accepted programs" + note, "plan_success_rate", "%",
         "% of programs run", 1.0, False),
        ("Path length per executed program" + note, "path_length_mean", "cells", "cells (mean)",
         1.0, False),
        ("Turns per executed program" + note, "turns_mean", "turns", "turns (mean)", 1.0, False),
        ("Plan CPU time per accepted program, median (timing)" + note, "plan_cpu_p50", unit,
         unit, scale, True),
    ]
    labels = [label for label, _ in conds]
    fig, axes = fp.new_figure(len(planner_spec))
    data = []
    for ax, (title, metric, u, ylabel, sc, timing) in zip(axes, planner_spec):
        means, errors = condition_series(figures, conds, "ours", "all", metric, sc)
        series = [{"label": "", "values": means, "errors": errors}]
        data.append(fp.bar_panel(ax, title, labels, series, u, ylabel, timing=timing))
        ax.tick_params(axis="x", labelrotation=12, labelsize=7)
    fp.save(fig, axes, os.path.join(run_dir, "planner"), "planner", data)
    return 2


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: replay_plots.py RUN_DIR\n")
        return 2
    run_dir = sys.argv[1]
    figures = fp.Figures(fp.read_figures(run_dir))
    variants = fp.read_variants(run_dir)
    drawn = 0
    for v in variants:
        drawn += variant_figures(run_dir, figures, v)
    if len(variants) > 1:
        drawn += cross_variant_figures(run_dir, figures, variants)
    print("plots: %d figures (PDF, SVG and .plotdata.json each) in %s" % (drawn, run_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
