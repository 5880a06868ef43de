#!/usr/bin/python3
"""Charts tools/study_normals.sh's CSV: normal error and map error, with and without the search."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main(path, out):
    rows = list(csv.DictReader(open(path)))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for ax, case, label in ((axes[0], "slope", "relief slope (deg)"), (axes[1], "noise", "noise (relative)")):
        for normals, style in (("no", "o--"), ("yes", "s-")):
            pts = [r for r in rows if r["case"] == case and r["normals"] == normals]
            x = [float(r["value"]) for r in pts]
            ax.plot(x, [float(r["normal_error_relief_deg"]) for r in pts], style, color="tab:blue",
                    label="normal error over relief, search " + normals)
            ax.plot(x, [float(r["false_tilt_flat_deg"]) for r in pts], style, color="tab:green",
                    label="false tilt on flat areas, search " + normals)
            ax2 = ax.twinx() if normals == "no" else ax2
            ax2.plot(x, [float(r["map_error"]) for r in pts], style, color="tab:red",
                     label="map error, search " + normals)
        ax.axhline(2.0, color="tab:blue", lw=0.5)
        ax.axhline(0.5, color="tab:green", lw=0.5)
        ax.set_xlabel(label)
        ax.set_ylabel("degrees")
        ax2.set_ylabel("map error (median log-space RMSE)", color="tab:red")
        ax.legend(fontsize=7, loc="upper left")
    other = [r for r in rows if r["case"] in ("material", "fibre")]
    names = sorted({r["case"] + " " + r["value"] for r in other})
    ax = axes[2]
    for i, name in enumerate(names):
        for j, normals in enumerate(("no", "yes")):
            r = [r for r in other if r["case"] + " " + r["value"] == name and r["normals"] == normals][0]
            ax.bar(i * 3 + j, float(r["normal_error_relief_deg"]), color="tab:blue" if normals == "yes" else "lightsteelblue")
            ax.text(i * 3 + j, float(r["normal_error_relief_deg"]), "map %.3f\n%.1f s" % (float(r["map_error"]), float(r["seconds"])),
                    ha="center", va="bottom", fontsize=7)
    ax.set_xticks([i * 3 + 0.5 for i in range(len(names))])
    ax.set_xticklabels(names, fontsize=8)
    ax.set_ylabel("normal error over relief (deg); light: assumed flat")
    fig.suptitle("per-pixel normal search (independent, 128 x 128 card, 4 deg field of view, seed 20 directions)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote " + out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
