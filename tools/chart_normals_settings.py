"""Chart of tools/study_normals_settings.sh's CSV: per capture, the relief's median normal error
against the worst validation view's relative RMS over the same view's with the search off (below
1: every view better than without the search), one point per variant of the search's settings in
the CSV's order (the plan's own settings labelled "as planned"). Usage: chart_normals_settings.py
CSV PNG"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path, png):
    rows = list(csv.DictReader(open(path)))
    off = {r["session"]: r for r in rows if r["search"] == "off"}
    runs = defaultdict(list)
    for r in rows:
        if r["search"] == "on" and r["session"] in off:
            base = off[r["session"]]
            ratios = [float(r[v]) / float(base[v]) for v in ("view1", "view2", "view3")
                      if r[v] and base[v]]
            runs[r["session"]].append((r["variant"], float(r["relief_deg"]), max(ratios)))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for session, points in sorted(runs.items()):
        ax.plot([p[1] for p in points], [p[2] for p in points], "o-", label=session)
        for variant, relief, ratio in points:
            ax.annotate("as planned" if variant == "on" else variant, (relief, ratio), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
    ax.axvline(2.0, color="grey", ls="--", lw=0.8)
    ax.axhline(1.0, color="grey", ls="--", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("median normal error over the relief (deg; the issue's goal: 2)")
    ax.set_ylabel("worst validation view, relative RMS / search off's")
    ax.set_title("The normal search's settings (labelled) through acqd")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main(*sys.argv[1:3])
