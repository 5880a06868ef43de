"""Chart of tools/study_normals_settings.sh's CSV: per capture, the relief's median normal error
against the worst validation view's relative RMS over the same view's with the search off (below
1: every view better than without the search), against the capture and, where the CSV has the
columns (a simulated session), against the true materials' render; one point per variant of the
search's settings in the CSV's order (the plan's own settings labelled "as planned"). Usage:
chart_normals_settings.py CSV PNG"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def ratio(run, base, column):
    """The run's figure over the search off's, None where either lacks it (a CSV from before the
    column, or a session without the truth)."""
    value, off = run.get(column), base.get(column)
    return float(value) / float(off) if value and off and float(off) > 0 else None


def every_view(runs):
    """Per view of each (run, search off's run): (view, against the capture, against the truth),
    each as the run's relative RMS over the search off's; only views with both."""
    views = []
    for run, base in runs:
        for i in (1, 2, 3):
            pair = ratio(run, base, "view%d" % i), ratio(run, base, "truth%d" % i)
            if None not in pair:
                views.append((i,) + pair)
    return views


def plot_every_view(ax, views):
    for i, marker in zip((1, 2, 3), "os^"):
        points = [v for v in views if v[0] == i]
        ax.scatter([v[1] for v in points], [v[2] for v in points], marker=marker, s=18,
                   label="view %d of the plan's validation views" % i)
    ax.axvline(1.0, color="grey", ls="--", lw=0.8)
    ax.axhline(1.0, color="grey", ls="--", lw=0.8)
    worse = sum(v[1] > 1 for v in views), sum(v[2] > 1 for v in views)
    ax.set_xlabel("against the capture: relative RMS / search off's (worse: %d of %d)"
                  % (worse[0], len(views)))
    ax.set_ylabel("against the truth's render: / search off's (worse: %d of %d)"
                  % (worse[1], len(views)))
    ax.set_title("Every validation view, every run with the search on", fontsize=10)
    ax.legend(fontsize=7)


def worst_views(runs, columns):
    """Per session, its runs' (variant, relief, worst of the views' ratios to the search off)."""
    points = defaultdict(list)
    for run, base in runs:
        ratios = [r for r in (ratio(run, base, c) for c in columns) if r is not None]
        if ratios:
            points[run["session"]].append((run["variant"], float(run["relief_deg"]), max(ratios)))
    return points


def plot_worst_views(ax, points, label):
    for session, run_points in sorted(points.items()):
        ax.plot([p[1] for p in run_points], [p[2] for p in run_points], "o-", label=session)
        for variant, relief, worst in run_points:
            ax.annotate("as planned" if variant == "on" else variant, (relief, worst),
                        fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.axvline(2.0, color="grey", ls="--", lw=0.8)
    ax.axhline(1.0, color="grey", ls="--", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("median normal error over the relief (deg; the issue's goal: 2)")
    ax.set_ylabel("worst validation view, relative RMS / search off's")
    ax.set_title("The normal search's settings (labelled), " + label, fontsize=10)
    ax.legend(fontsize=7)


def main(path, png):
    rows = list(csv.DictReader(open(path)))
    off = {r["session"]: r for r in rows if r["search"] == "off"}
    runs = [(r, off[r["session"]]) for r in rows if r["search"] == "on" and r["session"] in off]
    # Per panel: the views' columns and the axis's label. Against the truth (simulation only):
    # the map's render against the true materials', where the capture's own noise and
    # registration (up to 0.56 of relative RMS at a glossy ink's highlights: floor1-3) are left
    # out. A panel without figures is left out.
    panels = [(worst_views(runs, columns), label)
              for columns, label in ((("view1", "view2", "view3"), "against the capture"),
                                     (("truth1", "truth2", "truth3"),
                                      "against the true materials' render"))]
    panels = [(points, label) for points, label in panels if points]
    views = every_view(runs)
    count = len(panels) + bool(views)
    fig, axes = plt.subplots(1, count, figsize=(7.5 * count, 5), squeeze=False)
    for ax, (points, label) in zip(axes[0], panels):
        plot_worst_views(ax, points, label)
    if views:
        plot_every_view(axes[0][-1], views)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main(*sys.argv[1:3])
