"""What averaging the map's renders over the camera pixel's footprint changes (docs/
reconstruction.md, "A camera pixel's footprint in the map's renders"): runs of
tools/study_normals_settings.sh on captures made with `sim.pixel_samples: 4`, without the
footprint (BEFORE) and with it (AFTER). Left: every validation view's relative RMS with the
search over without it, against the capture, before (x) against after (y); right: the same
against the true materials' render (truth1-3). Below 1 the search is better than without it;
below the diagonal the footprint helps.
A BEFORE of CSV#VARIANT takes that variant's rows as the search on (e.g. nofoot, run with
`-- nofoot:pixel_footprint=false`); the search off always comes from AFTER. Usage:
chart_footprint.py PNG LABEL:BEFORE[#VARIANT]:AFTER..."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from chart_capture_sampling import label_log_axes, save  # noqa: E402
from chart_normals_settings import ratio  # noqa: E402


def rows_of(spec):
    """{session: row} of the CSV's variant (spec CSV#VARIANT, default "on")."""
    path, _, variant = spec.partition("#")
    variant = variant or "on"
    return {r["session"]: r for r in csv.DictReader(open(path)) if r["variant"] == variant}


def ratios(before, after, off, prefix):
    """(before, after) of on / off per session and view, for columns prefix1-3."""
    points = []
    for session in sorted(set(before) & set(after) & set(off)):
        for i in (1, 2, 3):
            column = "%s%d" % (prefix, i)
            pair = (ratio(before[session], off[session], column),
                    ratio(after[session], off[session], column))
            if None not in pair:
                points.append(pair)
    return points


def main(png, *specs):
    fig, panels = plt.subplots(1, 2, figsize=(13, 5.5))
    for spec, marker in zip(specs, "os^D"):
        label, before_spec, after_spec = spec.split(":")
        off = rows_of(after_spec + "#off")
        for ax, prefix in zip(panels, ("view", "truth")):
            points = ratios(rows_of(before_spec), rows_of(after_spec), off, prefix)
            worse = sum(p[0] > 1 for p in points), sum(p[1] > 1 for p in points)
            ax.scatter([p[0] for p in points], [p[1] for p in points], marker=marker, s=20,
                       label="%s: worse %d -> %d of %d" % (label, worse[0], worse[1], len(points)))
    for ax, what in zip(panels, ("the capture", "the true materials' render")):
        ax.axvline(1.0, color="grey", ls="--", lw=0.8)
        ax.axhline(1.0, color="grey", ls="--", lw=0.8)
        lo, hi = min(ax.get_xlim()[0], ax.get_ylim()[0]), max(ax.get_xlim()[1], ax.get_ylim()[1])
        ax.plot([lo, hi], [lo, hi], color="grey", lw=0.6)  # below it the footprint helps
        label_log_axes(ax, ("without the footprint: search on / off",
                            "with the footprint: search on / off",
                            "Each validation view against %s, relative RMS" % what))
    save(fig, png)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
