"""Shared plotting rules for Flipper's run folders (docs/experiments.md §5).

The plot scripts read only a run's CSV files (figures.csv, variants.csv) and write, for each
figure, PDF and SVG and `<figure>.plotdata.json`: the values, error bars, labels, axis ranges and
units that were plotted, so tests check what a figure shows without looking at pixels.

The rules every figure follows:
- axes fitted to the data: a value axis ends a little above the largest bar (room for its label),
  never at a round number far beyond it; when the bars differ, but by little relative to their
  size (less than a fifth of the largest), the axis is zoomed onto them and the title says so;
- every bar carries its value as a label;
- durations below 1 ms are drawn in µs (no "0.0 ms");
- error bars over seeds (sample standard deviation) where a condition has several seeds;
- panels are stacked, each the full width of the figure;
- output is byte-for-byte deterministic: fixed SVG hash salt, no dates in the metadata.
"""

import csv
import json
import math
import os
import sys

NO_MATPLOTLIB = 3  # the exit status flipper reads as "this Python has no matplotlib"

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:  # flipper then tries another Python, or says how to get the plots
    sys.exit(NO_MATPLOTLIB)

os.environ.setdefault("SOURCE_DATE_EPOCH", "0")
matplotlib.rcParams.update({
    "svg.hashsalt": "flipper",  # stable ids in the SVG
    "svg.fonttype": "none",     # text stays text (searchable, smaller)
    "pdf.fonttype": 42,
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.spines.top": False,
    "axes.spines.right": False,
})

WIDTH_IN = 9.0       # every figure: panels the full width
PANEL_HEIGHT_IN = 2.9
COLORS = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3",
          "#8c8c8c", "#ccb974", "#64b5cd"]


def read_figures(run_dir):
    """figures.csv as a list of dicts, `value` a float (read back exactly) and `timing` a bool."""
    rows = []
    with open(os.path.join(run_dir, "figures.csv"), newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            r["value"] = float(r["value"])
            r["timing"] = r["timing"] == "1"
            rows.append(r)
    return rows


def read_variants(run_dir):
    """variants.csv as a list of dicts (variant, directory, condition, seed), in run order."""
    with open(os.path.join(run_dir, "variants.csv"), newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


class Figures:
    """figures.csv looked up by (variant, source, group, metric)."""

    def __init__(self, rows):
        self.rows = rows
        self.values = {(r["variant"], r["source"], r["group"], r["metric"]): r["value"]
                       for r in rows}

    def get(self, variant, source, group, metric, default=0.0):
        return self.values.get((variant, source, group, metric), default)

    def groups(self, variant, source, metric):
        return [r["group"] for r in self.rows
                if r["variant"] == variant and r["source"] == source and r["metric"] == metric]


def conditions(variants):
    """Conditions in run order, each with its variants (the seeds of that condition)."""
    out = {}
    for v in variants:
        out.setdefault(v["condition"], []).append(v["variant"])
    return list(out.items())


def over_seeds(values):
    """mean, sample sd (0 for one value), min, max of a condition's values over its seeds."""
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in values) / (n - 1)) if n > 1 else 0.0
    return mean, sd, min(values), max(values)


def time_unit(values_ms):
    """("µs", 1000) when every duration is below 1 ms, ("s", 0.001) from 10 s, else ("ms", 1)."""
    top = max([abs(v) for v in values_ms] + [0.0])
    if top < 1.0:
        return "µs", 1000.0
    if top >= 10000.0:
        return "s", 0.001
    return "ms", 1.0


def label_text(value, unit):
    """A bar's value label: one decimal for percentages, whole counts as integers, else 3
    significant digits."""
    if unit == "%":
        return "%.1f" % value
    if value == int(value) and abs(value) < 1e9:
        return "%d" % value
    if abs(value) >= 1000:  # never "1.23e+04" beside integers
        return "%.0f" % value
    return "%.3g" % value


def fit_axis(lows, highs):
    """The value axis for bars spanning [min(lows), max(highs)]: (ymin, ymax, zoomed)."""
    if not highs or max(highs) <= 0:
        return 0.0, 1.0, False
    lo, hi = min(lows), max(highs)
    if lo > 0 and 0 < (hi - lo) < 0.2 * hi:
        margin = max((hi - lo) * 0.6, hi * 0.01)
        return max(0.0, lo - margin), hi + margin, True
    return min(lo, 0.0), hi * 1.12, False


def bar_panel(ax, title, categories, series, unit, ylabel, timing=False, integer=False):
    """Grouped bars: `series` is a list of {"label", "values", "errors"} (errors: None or a pair
    of lists [below, above] in the values' unit). Returns the panel's plot data."""
    n = max(1, len(series))
    width = 0.8 / n
    if unit == "%":  # a share is within 0-100: so are its error bars and its axis
        for s in series:
            errs = s.get("errors")
            if errs:
                s["errors"] = [[min(b, v) for b, v in zip(errs[0], s["values"])],
                               [min(a, 100.0 - v) for a, v in zip(errs[1], s["values"])]]
    lows, highs = [], []
    for s in series:
        errs = s.get("errors")
        for i, v in enumerate(s["values"]):
            below = errs[0][i] if errs else 0.0
            above = errs[1][i] if errs else 0.0
            lows.append(v - below)
            highs.append(v + above)
    ymin, ymax, zoomed = fit_axis(lows, highs)
    if unit == "%":
        ymax = min(ymax, 100.0)
        ymin = min(ymin, ymax - 1.0)
    labels_out = []
    for k, s in enumerate(series):
        xs = [i - 0.4 + width * (k + 0.5) for i in range(len(categories))]
        errs = s.get("errors")
        bars = ax.bar(xs, s["values"], width * 0.92, color=COLORS[k % len(COLORS)],
                      label=s["label"],
                      yerr=errs if errs else None, capsize=3 if errs else 0,
                      error_kw={"elinewidth": 0.9, "ecolor": "black"})
        texts = [label_text(v, unit) for v in s["values"]]
        ax.bar_label(bars, labels=texts, padding=2, fontsize=7)
        labels_out.append(texts)
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels(categories)
    ax.set_ylim(ymin, ymax)
    # Plain tick labels: no scientific notation, no offset ("1e4", "+1.23e3") beside integers.
    ax.ticklabel_format(axis="y", style="plain", useOffset=False)
    ax.set_title(title + (" (axis zoomed: it does not start at 0)" if zoomed and ymin > 0 else ""))
    ax.set_ylabel(ylabel)
    if integer:
        ax.yaxis.get_major_locator().set_params(integer=True)
    if len(series) > 1:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=min(len(series), 3),
                  fontsize=7, frameon=False)
    return {
        "title": ax.get_title(),
        "ylabel": ylabel,
        "unit": unit,
        "timing": timing,
        "categories": list(categories),
        "series": [{"label": s["label"], "values": s["values"],
                    "errors": s.get("errors"), "value_labels": labels_out[k]}
                   for k, s in enumerate(series)],
        "ylim": [ymin, ymax],
        "zoomed": zoomed and ymin > 0,
    }


def new_figure(panels):
    fig, axes = plt.subplots(panels, 1, figsize=(WIDTH_IN, PANEL_HEIGHT_IN * panels + 0.3),
                             squeeze=False)
    return fig, [a[0] for a in axes]


def save(fig, axes, stem, name, panels_data):
    """Writes stem.pdf, stem.svg and stem.plotdata.json (panels' data plus their widths)."""
    fig.tight_layout(h_pad=2.0)
    for ax, data in zip(axes, panels_data):
        data["width_fraction"] = round(ax.get_position().width, 4)
    fig.savefig(stem + ".svg", metadata={"Date": None})
    fig.savefig(stem + ".pdf", metadata={"CreationDate": None, "ModDate": None})
    plt.close(fig)
    with open(stem + ".plotdata.json", "w", encoding="utf-8") as f:
        json.dump({"figure": name, "panels": panels_data}, f, indent=1, sort_keys=True,
                  ensure_ascii=False)
        f.write("\n")
