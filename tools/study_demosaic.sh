#!/bin/sh
# The demosaic study (issue 16; docs/colour.md): where demosaicing goes and which method, on the
# simulated card through the simulated Bayer camera. Prints the table and writes
# out/study/demosaic/{results.csv,demosaic.png}.
#   tools/study_demosaic.sh [SIZE=480]      (after a build: build/tests/bench_demosaic)
set -e
cd "$(dirname "$0")/.."
out=out/study/demosaic
mkdir -p "$out"
build/tests/bench_demosaic "${1:-480}" "$out/results.csv"
/usr/bin/python3 - "$out/results.csv" "$out/demosaic.png" <<'PY'
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1])))
labels = []
for r in rows:
    key = r["order"] + "\n" + r["method"]
    if key not in labels:
        labels.append(key)
fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
for ax, region in zip(axes, ["interior", "edges"]):
    for k, (noise, stat, colour) in enumerate([("on", "median_de2000", "C0"), ("on", "p95_de2000", "C1"),
                                               ("off", "median_de2000", "C2"), ("off", "p95_de2000", "C3")]):
        values = [float(r[stat]) for key in labels for r in rows
                  if r["order"] + "\n" + r["method"] == key and r["region"] == region and r["noise"] == noise]
        xs = [i + (k - 1.5) * 0.2 for i in range(len(labels))]
        ax.bar(xs, values, 0.2, color=colour,
               label="%s, sensor noise %s" % ("median" if stat.startswith("median") else "95th percentile", noise))
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylabel("CIEDE2000 against the rendered truth")
    ax.set_title("card " + ("interior" if region == "interior" else "printed edges (within 2 px of another ink)"))
axes[0].legend(fontsize=7)
fig.suptitle("demosaic: order and method (RGGB, cross-talk, warm light, 3-exposure bracket)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=100)
print("chart:", sys.argv[2])
PY
