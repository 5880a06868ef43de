#!/usr/bin/python3
"""The model-order chart of issue 18 (item 5): the cross-validated median log-space RMSE, per
source and basis, against the ridge strength eta for each k, from the runs of
tools/study_basis_generalisation.py written as out/study/basis_cv_k{K}_eta{ETA}/per_material.csv.
Prints the table and writes out/study/basis_cv_grid.png.

  tools/chart_basis_cv_grid.py [--study out/study]"""
import argparse
import csv
import glob
import os
import re
import statistics

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--study", default=os.path.join(ROOT, "out", "study"))
    a = ap.parse_args()
    table = {}  # (k, eta) -> {(basis, source): median}
    for path in glob.glob(os.path.join(a.study, "basis_cv_k*_eta*", "per_material.csv")):
        m = re.search(r"basis_cv_k(\d+)_eta([\d.]+)", path)
        k, eta = int(m.group(1)), float(m.group(2))
        channels = {}
        with open(path) as f:
            for row in csv.DictReader(f):
                key = (row["basis"], row["source"])
                channels.setdefault(key, []).extend(
                    float(row[c]) for c in ("log_rmse_R", "log_rmse_G", "log_rmse_B"))
        table[(k, eta)] = {key: statistics.median(v) for key, v in channels.items()}
    if not table:
        raise SystemExit("no runs under " + a.study + " (run tools/study_basis_generalisation.py)")
    keys = [("merl", "rgl"), ("merl+rgl", "rgl"), ("merl", "merl"), ("merl+rgl", "merl")]
    print(f"{'k':>3} {'eta':>6}  " + "  ".join(f"{b}/{s:<5}" for b, s in keys))
    for (k, eta) in sorted(table):
        print(f"{k:3d} {eta:6g}  " + "  ".join(f"{table[(k, eta)].get(key, float('nan')):>12.4f}"
                                                for key in keys))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=False)
    for ax, source in zip(axes, ("rgl", "merl")):
        for k in sorted({k for k, _ in table}):
            etas = sorted(e for kk, e in table if kk == k)
            for basis, style in (("merl", "--"), ("merl+rgl", "-")):
                ax.plot(etas, [table[(k, e)][(basis, source)] for e in etas], style, marker="o",
                        label=f"{basis} basis, k = {k}")
        ax.set_xscale("log")
        ax.set_xlabel("eta (ridge strength)")
        ax.set_ylabel("median log-space RMSE, cross-validated")
        ax.set_title(f"{source.upper()} materials, held out")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(a.study, "basis_cv_grid.png")
    fig.savefig(out, dpi=100)
    print("chart:", out)


if __name__ == "__main__":
    main()
