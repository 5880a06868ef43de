#!/usr/bin/python3
"""The model-order chart of issue 18 (item 5): the cross-validated median log-space RMSE, per
source and basis, against the ridge strength eta for each k and direction set (the given seed's,
and those optimised per fold where a run had --optimise), from the runs of
tools/study_basis_generalisation.py written as out/study/basis_cv_k{K}_eta{ETA}[_opt]/per_material.csv.
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
    table = {}  # (k, eta, directions) -> {(basis, source): median}
    for path in sorted(glob.glob(os.path.join(a.study, "basis_cv_k*_eta*", "per_material.csv"))):
        m = re.search(r"basis_cv_k(\d+)_eta([\d.]+)", path)
        k, eta = int(m.group(1)), float(m.group(2))
        channels = {}
        with open(path) as f:
            for row in csv.DictReader(f):
                key = (row.get("directions", "given"), row["basis"], row["source"])
                channels.setdefault(key, []).extend(
                    float(row[c]) for c in ("log_rmse_R", "log_rmse_G", "log_rmse_B"))
        for (d, basis, source), v in channels.items():
            table.setdefault((k, eta, d), {})[(basis, source)] = statistics.median(v)
    if not table:
        raise SystemExit("no runs under " + a.study + " (run tools/study_basis_generalisation.py)")
    keys = [("merl", "rgl"), ("merl+rgl", "rgl"), ("merl", "merl"), ("merl+rgl", "merl")]
    print(f"{'k':>3} {'eta':>6} {'directions':>10}  " + "  ".join(f"{b}/{s:<5}" for b, s in keys))
    for (k, eta, d) in sorted(table):
        print(f"{k:3d} {eta:6g} {d:>10}  " + "  ".join(
            f"{table[(k, eta, d)].get(key, float('nan')):>12.4f}" for key in keys))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=False)
    for ax, source in zip(axes, ("rgl", "merl")):
        for k, d in sorted({(k, d) for k, _, d in table}):
            etas = sorted(e for kk, e, dd in table if kk == k and dd == d)
            if len(etas) < 2 and k != 20:
                continue  # a lone point of another k: in the table, not worth a line
            for basis, style in (("merl", "--"), ("merl+rgl", "-")):
                ax.plot(etas, [table[(k, e, d)][(basis, source)] for e in etas], style,
                        marker="o" if d == "given" else "s", label=f"{basis} basis, k = {k}, {d}")
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
