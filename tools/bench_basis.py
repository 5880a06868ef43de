#!/usr/bin/python3
"""Benchmark of the basis build on all 100 materials: `acq basis build` against the
straightforward numpy reference (tools/reference_basis.py) in the same run. Prints wall time
and peak memory (max RSS from /usr/bin/time) for both and their ratios; writes a CSV and a
chart. Goal (issue 2): at least 2x faster than the reference and under 4 GiB peak.

  tools/bench_basis.py [--build build] [--out out/bench/basis] [--skip-reference]"""
import argparse
import csv
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def timed(cmd):
    """Runs cmd under /usr/bin/time; returns (wall seconds, peak MiB)."""
    res = subprocess.run(["/usr/bin/time", "-f", "TIME %e %M"] + cmd, capture_output=True,
                         text=True)
    if res.returncode != 0:
        sys.exit(f"benchmark: {' '.join(cmd)} failed:\n{res.stdout}\n{res.stderr}")
    m = re.search(r"TIME ([\d.]+) (\d+)", res.stderr)
    return float(m.group(1)), int(m.group(2)) / 1024.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "basis"))
    ap.add_argument("--materials", default=os.path.join(ROOT, "data", "nbrdf", "merl"))
    ap.add_argument("--skip-reference", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    rows = []
    ours = timed([os.path.join(a.build, "src", "cli", "acq"), "basis", "build", a.materials,
                  "-o", os.path.join(a.out, "basis100.acqb"), "--quiet"])
    rows.append(("acq basis build (C++)", *ours))
    if not a.skip_reference:
        ref = timed([sys.executable, os.path.join(HERE, "reference_basis.py"), a.materials])
        rows.append(("numpy reference", *ref))

    print(f"{'implementation':<24} {'wall s':>8} {'peak MiB':>10}")
    for name, wall, peak in rows:
        print(f"{name:<24} {wall:8.1f} {peak:10.0f}")
    if len(rows) == 2:
        print(f"speed-up: {rows[1][1] / rows[0][1]:.1f}x faster; "
              f"memory: {rows[1][2] / rows[0][2]:.1f}x less; "
              f"ours under 4 GiB: {'yes' if rows[0][2] < 4096 else 'NO'}")
    with open(os.path.join(a.out, "basis_build.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["implementation", "wall_s", "peak_mib"])
        w.writerows(rows)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    names = [r[0] for r in rows]
    for ax, col, label in ((axes[0], 1, "wall time (s)"), (axes[1], 2, "peak memory (MiB)")):
        ax.bar(names, [r[col] for r in rows], color=["tab:blue", "tab:gray"][: len(rows)])
        ax.set_ylabel(label)
        for i, r in enumerate(rows):
            ax.text(i, r[col], f"{r[col]:.0f}", ha="center", va="bottom")
    axes[1].axhline(4096, color="tab:red", ls="--", label="4 GiB goal")
    axes[1].legend()
    fig.suptitle("Basis build, all 100 MERL materials (neural-BRDF fits), 2 cores")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "basis_build.png"), dpi=100)
    print(f"wrote {a.out}/basis_build.csv and basis_build.png")


if __name__ == "__main__":
    main()
