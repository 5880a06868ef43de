"""What comparing the map's render sampled the way each validation capture was changes
(docs/reconstruction.md, "A prediction sampled as the capture was"): two runs of
tools/study_normals_settings.sh on the same captures, one by the code that compared at the
reference pixels' own points (BEFORE) and one by the code that samples as the capture was
(AFTER). Left: every validation view's relative RMS with the search on over the search off's,
before (x) against after (y); below 1 is better than without the search. Right: the true
materials' render against the capture (floor1-3, what no model of the sample goes under), before
against after; below the diagonal the truth is nearer the capture. One marker per pair of CSVs
(e.g. the default camera and an integrating one). Usage:
chart_capture_sampling.py PNG LABEL:BEFORE_CSV:AFTER_CSV..."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from chart_normals_settings import ratio  # noqa: E402


def runs_by_search(path):
    """{(session, "on" | "off"): row} of a study's CSV (its variants other than on are left out)."""
    return {(r["session"], r["search"]): r for r in csv.DictReader(open(path))
            if r["variant"] in ("on", "off")}


def paired_views(before, after):
    """Per session and view: (on / off before, on / off after, floor before, floor after)."""
    points = []
    for session in sorted({s for s, _ in after}):
        keys = (session, "on"), (session, "off")
        if not all(k in before and k in after for k in keys):
            continue
        for i in (1, 2, 3):
            column = "view%d" % i
            pair = (ratio(before[keys[0]], before[keys[1]], column),
                    ratio(after[keys[0]], after[keys[1]], column))
            floors = before[keys[1]].get("floor%d" % i), after[keys[1]].get("floor%d" % i)
            if None not in pair and all(floors):
                points.append(pair + tuple(float(f) for f in floors))
    return points


def label_log_axes(ax, labels):
    """Both axes logarithmic; labels: x's, y's and the title."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_title(labels[2], fontsize=10)
    ax.legend(fontsize=8)


def save(fig, png):
    """The figure laid out and written to png."""
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print("wrote", png)


def main(png, *pairs):
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5.5))
    for spec, marker in zip(pairs, "os^D"):
        label, before, after = spec.split(":")
        points = paired_views(runs_by_search(before), runs_by_search(after))
        worse = sum(p[0] > 1 for p in points), sum(p[1] > 1 for p in points)
        left.scatter([p[0] for p in points], [p[1] for p in points], marker=marker, s=20,
                     label="%s: worse %d -> %d of %d" % (label, worse[0], worse[1], len(points)))
        nearer = sum(p[3] < p[2] for p in points)
        right.scatter([p[2] for p in points], [p[3] for p in points], marker=marker, s=20,
                      label="%s: nearer in %d of %d" % (label, nearer, len(points)))
    left.axvline(1.0, color="grey", ls="--", lw=0.8)
    left.axhline(1.0, color="grey", ls="--", lw=0.8)
    label_log_axes(left, ("at the reference pixels' own points: search on / off",
                          "sampled as the capture was: search on / off",
                          "Each validation view, relative RMS with the search over without"))
    lo = min(right.get_xlim()[0], right.get_ylim()[0])
    hi = max(right.get_xlim()[1], right.get_ylim()[1])
    right.plot([lo, hi], [lo, hi], color="grey", ls="--", lw=0.8)
    label_log_axes(right, ("the truth against the capture, at the pixels' own points",
                           "the truth against the capture, sampled as the capture was",
                           "What no model of the sample goes under (relative RMS)"))
    save(fig, png)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
