#!/usr/bin/python3
"""Charts tools/study_normals.sh's CSVs: normal error, false tilt and map error per search
criterion; and, given the second CSV, each search method's time against its normal error."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

SEARCHES = (("none", "lightgrey", "o:"), ("fit", "tab:orange", "^--"),
            ("one-centre", "tab:green", "d-."), ("centre", "tab:blue", "s-"),
            ("untrimmed", "tab:purple", "v-"))


def line_panels(rows, axes):
    for ax, case, label in ((axes[0], "slope", "relief slope (deg)"), (axes[1], "noise", "noise (relative)")):
        ax2 = ax.twinx()
        for search, colour, style in SEARCHES:
            pts = [r for r in rows if r["case"] == case and r["search"] == search]
            x = [float(r["value"]) for r in pts]
            ax.plot(x, [float(r["normal_error_relief_deg"]) for r in pts], style, color=colour,
                    label="normal error over relief, " + search)
            if search != "none":
                ax.plot(x, [float(r["false_tilt_flat_deg"]) for r in pts], style, color=colour,
                        alpha=0.45, label="false tilt on flat areas, " + search)
            ax2.plot(x, [float(r["map_error"]) for r in pts], style, color=colour, lw=0.8)
            if case == "slope" and search == "centre":  # where the search must refuse
                for r, xi in zip(pts, x):
                    ax.annotate("%s refused" % r["refused"], (xi, float(r["normal_error_relief_deg"])),
                                fontsize=6, color=colour, textcoords="offset points", xytext=(3, -9))
        ax.axhline(2.0, color="k", lw=0.4)
        ax.axhline(0.5, color="k", lw=0.4, ls="--")
        ax.set_xlabel(label)
        ax.set_ylabel("degrees (goals: 2 over relief, 0.5 flat)")
        ax2.set_ylabel("map error, thin lines (median log-space RMSE)")
        ax.legend(fontsize=6, loc="upper left")


def bar_panel(rows, ax, key, ylabel):
    other = [r for r in rows if r["case"] in ("material", "flat", "pooled")]
    names = []
    for r in other:
        name = r["case"] + " " + r["value"]
        if name not in names:
            names.append(name)
    for i, name in enumerate(names):
        for j, (search, colour, _) in enumerate(SEARCHES):
            r = [r for r in other if r["case"] + " " + r["value"] == name and r["search"] == search][0]
            v = float(r[key])
            ax.bar(i * 6 + j, v if v == v else 0, color=colour)
            if key == "map_error":
                ax.text(i * 6 + j, v, "%.3f" % v, ha="center", va="bottom", fontsize=5, rotation=90)
    ax.set_xticks([i * 6 + 2 for i in range(len(names))])
    ax.set_xticklabels(names, fontsize=7, rotation=30, ha="right")
    ax.set_ylabel(ylabel)


def main(path, out):
    rows = list(csv.DictReader(open(path)))
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.6))
    line_panels(rows, axes)
    bar_panel(rows, axes[2], "normal_error_relief_deg", "normal error over relief (deg)")
    bar_panel(rows, axes[3], "map_error", "map error (grey none, orange fit, green one centre, blue centre,\npurple centre with every view scored)")
    fig.suptitle("per-pixel normal search: none / own fit / one group centre / centres or two mixed, "
                 "the worst view left out / the same, every view scored (128 x 128, 4 deg field of view, "
                 "seed 20 directions)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote " + out)


def search_chart(path, out):
    rows = list(csv.DictReader(open(path)))
    fig, ax = plt.subplots(figsize=(7, 4.6))
    for method, colour in (("grid", "tab:blue"), ("quadratic", "tab:green")):
        pts = [r for r in rows if r["method"] == method]
        for key, style, what in (("normal_error_relief_deg", "s-", "over the relief"),
                                 ("one_material_deg", "o:", "over relief of one material")):
            ax.plot([float(r["search_seconds"]) for r in pts], [float(r[key]) for r in pts], style,
                    color=colour, label=method + ", " + what)
        for r in pts:
            ax.annotate("L%s r%s" % (r["levels"], r["coarse_reach"]),
                        (float(r["search_seconds"]), float(r["normal_error_relief_deg"])),
                        fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.axhline(2.0, color="k", lw=0.4)
    ax.set_xlabel("search time (s, 65,536 pixels, 2 cores)")
    ax.set_ylabel("median normal error (deg)")
    ax.set_title("normal search: time against error (L: refinement levels, r: coarse reach)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote " + out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
    if len(sys.argv) > 4:
        search_chart(sys.argv[3], sys.argv[4])
