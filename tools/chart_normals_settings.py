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


def worst_ratio(run, base, columns):
    """The largest of the views' figure over the search off's (None without the columns)."""
    ratios = [float(run[c]) / float(base[c]) for c in columns
              if run.get(c) and base.get(c) and float(base[c]) > 0]
    return max(ratios) if ratios else None


def every_view(rows, off):
    """Per view of each run with the search on: (session, view, against the capture, against the
    truth), each as the run's relative RMS over the search off's."""
    views = []
    for r in rows:
        base = off.get(r["session"])
        if r["search"] != "on" or base is None:
            continue
        for i in (1, 2, 3):
            cells = [r["view%d" % i], base["view%d" % i], r["truth%d" % i], base["truth%d" % i]]
            if all(cells) and float(cells[1]) > 0 and float(cells[3]) > 0:
                views.append((r["session"], i, float(cells[0]) / float(cells[1]),
                              float(cells[2]) / float(cells[3])))
    return views


def plot_every_view(ax, views):
    for i, marker in zip((1, 2, 3), "os^"):
        points = [v for v in views if v[1] == i]
        ax.scatter([v[2] for v in points], [v[3] for v in points], marker=marker, s=18,
                   label="view %d of the plan's validation views" % i)
    ax.axvline(1.0, color="grey", ls="--", lw=0.8)
    ax.axhline(1.0, color="grey", ls="--", lw=0.8)
    worse = sum(v[2] > 1 for v in views), sum(v[3] > 1 for v in views)
    ax.set_xlabel("against the capture: relative RMS / search off's (worse: %d of %d)"
                  % (worse[0], len(views)))
    ax.set_ylabel("against the truth's render: / search off's (worse: %d of %d)"
                  % (worse[1], len(views)))
    ax.set_title("Every validation view, every run with the search on", fontsize=10)
    ax.legend(fontsize=7)


def main(path, png):
    rows = list(csv.DictReader(open(path)))
    off = {r["session"]: r for r in rows if r["search"] == "off"}
    # Per panel: the views' columns and the axis's label. Against the truth (simulation only):
    # the map's render against the true materials', where the capture's own noise (up to 0.55 of
    # relative RMS at a glossy ink's highlights: floor1-3) is left out.
    panels = [(("view1", "view2", "view3"), "against the capture"),
              (("truth1", "truth2", "truth3"), "against the true materials' render")]
    panels = [p for p in panels
              if any(worst_ratio(r, off[r["session"]], p[0]) for r in rows
                     if r["search"] == "on" and r["session"] in off)]
    views = every_view(rows, off) if len(panels) == 2 else []
    columns = len(panels) + bool(views)
    fig, axes = plt.subplots(1, columns, figsize=(7.5 * columns, 5), squeeze=False)
    if views:
        plot_every_view(axes[0][-1], views)
    for ax, (columns, label) in zip(axes[0], panels):
        runs = defaultdict(list)
        for r in rows:
            if r["search"] == "on" and r["session"] in off:
                ratio = worst_ratio(r, off[r["session"]], columns)
                if ratio is not None:
                    runs[r["session"]].append((r["variant"], float(r["relief_deg"]), ratio))
        for session, points in sorted(runs.items()):
            ax.plot([p[1] for p in points], [p[2] for p in points], "o-", label=session)
            for variant, relief, ratio in points:
                ax.annotate("as planned" if variant == "on" else variant, (relief, ratio),
                            fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.axvline(2.0, color="grey", ls="--", lw=0.8)
        ax.axhline(1.0, color="grey", ls="--", lw=0.8)
        ax.set_yscale("log")
        ax.set_xlabel("median normal error over the relief (deg; the issue's goal: 2)")
        ax.set_ylabel("worst validation view, relative RMS / search off's")
        ax.set_title("The normal search's settings (labelled), " + label, fontsize=10)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main(*sys.argv[1:3])
