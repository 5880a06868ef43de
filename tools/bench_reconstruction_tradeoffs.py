#!/usr/bin/python3
"""Accuracy against time for the choices that cost time in the per-pixel reconstruction
(issue 7): rows shared by tiles of pixels (1 = every pixel its own), nearest against
interpolated rows, k, threads, and the kernel (float64 or float32 SIMD lanes, or one pixel at a
time with Eigen); at fields of view of 4 and 10 degrees. Each point is one
`acq reconstruct synthetic --score` run on a 512 x 512 card of four held-out materials with the
seed's 20 directions: error is the median per-pixel log-space RMSE against the ground truth,
time the solve alone. Writes out/bench/reconstruction/tradeoffs.{csv,png}.

  /usr/bin/python3 tools/bench_reconstruction_tradeoffs.py [--size 512] [--build build]

"Model no more than the scene needs": the default is the cheapest setting (least solve time over
both fields of view) whose error is within 0.5% of the most exact one (per-pixel interpolated
rows in float64) at 4 and 10 degrees. The chart marks it."""
import argparse
import csv
import os
import re
import sys

from synthetic_reconstruction import acq_from, add_common_options, reconstruct


def run(acq, basis, fov, size, extra, threads=2, repeat=3):
    """Least solve time of `repeat` runs (noise on a shared machine only ever adds time) and the
    error, which runs do not change."""
    times = []
    for _ in range(repeat):
        t, out = reconstruct(acq, basis, size, fov, "/tmp/acq-tradeoff.exr", ["--score", *extra],
                             threads)
        times.append(t)
    return min(times), float(re.search(r"ground truth: ([\d.]+)", out).group(1))


def main():
    ap = argparse.ArgumentParser()
    add_common_options(ap, 512)
    ap.add_argument("--from-csv", action="store_true", help="redraw the chart from tradeoffs.csv")
    a = ap.parse_args()
    acq = acq_from(a)
    rows = []
    csv_path = os.path.join(a.out, "tradeoffs.csv")
    if a.from_csv:
        with open(csv_path) as f:
            rows = [(int(r["fov_deg"]), r["lookup"], int(r["row_tile"]), int(r["k"]), int(r["threads"]),
                     float(r["solve_s"]), float(r["median_log_rmse"]), r["kernel"])
                    for r in csv.DictReader(f)]
    for fov in () if a.from_csv else (4, 10):
        for lookup in ("nearest", "interpolated"):
            for tile in (1, 2, 4, 8, 16, 32, 64):
                t, e = run(acq, a.basis, fov, a.size, ["--lookup", lookup, "--row-tile", str(tile)])
                rows.append((fov, lookup, tile, 20, 2, t, e, "lanes"))
                print(f"fov {fov:2d} {lookup:12s} tile {tile:3d}: {t:6.2f} s, error {e:.4f}")
        for k in (5, 10, 15):
            t, e = run(acq, a.basis, fov, a.size, ["--k", str(k), "--row-tile", "1"])
            rows.append((fov, "nearest", 1, k, 2, t, e, "lanes"))
            print(f"fov {fov:2d} k {k}: {t:6.2f} s, error {e:.4f}")
        t, e = run(acq, a.basis, fov, a.size, ["--row-tile", "1"], threads=1)
        rows.append((fov, "nearest", 1, 20, 1, t, e, "lanes"))
        print(f"fov {fov:2d} 1 thread: {t:6.2f} s, error {e:.4f}")
        for kernel in ("lanes-single", "one-pixel"):
            t, e = run(acq, a.basis, fov, a.size, ["--row-tile", "1", "--kernel", kernel])
            rows.append((fov, "nearest", 1, 20, 2, t, e, kernel))
            print(f"fov {fov:2d} kernel {kernel}: {t:6.2f} s, error {e:.4f}")
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["fov_deg", "lookup", "row_tile", "k", "threads", "solve_s", "median_log_rmse",
                    "kernel"])
        w.writerows(rows)

    def exact(fov):
        return [r for r in rows if r[0] == fov and r[1] == "interpolated" and r[2] == 1][0][6]

    def at(fov, lookup, tile):  # the method's k = 20, two threads, float64 lanes
        return [r for r in rows if r[0] == fov and r[1] == lookup and r[2] == tile and r[3] == 20
                and r[4] == 2 and r[7] == "lanes"][0]

    def within(lookup, tile):  # this tile and every smaller one: an error that dips by chance
        return all(at(f, lookup, u)[6] <= exact(f) * 1.005  # at one size does not count
                   for f in (4, 10) for u in sorted({r[2] for r in rows}) if u <= tile)
    # k stays the method's 20 (a modelling choice judged on held-out materials, charted here
    # for a look) and precision float64: float32 cannot evaluate the validity rule (condition
    # numbers above about 1e3 are lost in its normal matrix; tests/test_pixel_solver.cpp).
    # Solve times within 25% of the fastest are a tie, going to the smaller tile (the more exact
    # model): one setting's least-of-three time varies by about 15% between the two fields of
    # view, which do the same work (per-pixel rows: 0.21 and 0.24 s), and at 1024 x 1024 per-pixel
    # rows, 8 x 8 tiles and interpolated 16 x 16 tiles took 0.80-0.87, 0.80-0.82 and 0.75-0.80 s.
    eligible = sorted((sum(at(f, lookup, tile)[5] for f in (4, 10)), tile, lookup)
                      for lookup in ("nearest", "interpolated") for tile in sorted({r[2] for r in rows})
                      if within(lookup, tile))
    fastest = eligible[0][0]
    default_tile, _, lookup = min((tile, t, lookup) for t, tile, lookup in eligible
                                  if t <= 1.25 * fastest)
    print(f"default: {lookup} rows, row tile {default_tile} (the least solve time within 0.5% of "
          f"exact at 4 and 10 degrees, ties of 25% to the smaller tile)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    mp = a.size * a.size / 1e6
    for ax, fov in zip(axes, (4, 10)):
        in_fov = [r for r in rows if r[0] == fov]
        exact_row = [r for r in in_fov if r[1] == "interpolated" and r[2] == 1][0]
        for curve, colour in (("nearest", "tab:blue"), ("interpolated", "tab:orange")):
            pts = [(r[5], r[6], r[2]) for r in sorted(in_fov, key=lambda r: r[2])
                   if r[1] == curve and r[3] == 20 and r[4] == 2 and r[7] == "lanes"]
            ax.plot([mp / p[0] for p in pts], [p[1] for p in pts], "o-", color=colour,
                    label=f"{curve} rows, tile 1..64 px")
            for p in pts:
                ax.annotate(str(p[2]), (mp / p[0], p[1]), fontsize=7, xytext=(3, 3),
                            textcoords="offset points")
        ks = [r for r in in_fov if r[3] != 20]
        ax.plot([mp / r[5] for r in ks], [r[6] for r in ks], "s", color="tab:green",
                label="k = 5, 10, 15 (per pixel)")
        one = [r for r in in_fov if r[4] == 1][0]
        ax.plot(mp / one[5], one[6], "^", color="tab:red", label="1 thread (per pixel)")
        for kernel, marker, label in (("lanes-single", "D", "float32 lanes (per pixel)"),
                                      ("one-pixel", "v", "one pixel at a time, Eigen")):
            r = [r for r in in_fov if r[7] == kernel][0]
            ax.plot(mp / r[5], r[6], marker, color="tab:purple", label=label)
        best = at(fov, lookup, default_tile)
        ax.plot(mp / best[5], best[6], "k*", ms=16,
                label=f"default: {lookup} rows, tile {default_tile} (within 0.5% at 4 and 10 deg)")
        ax.axhline(exact_row[6] * 1.005, color="gray", ls=":", lw=1, label="exact + 0.5%")
        ax.set_xscale("log")
        ax.set_xlabel("solve throughput (megapixels/s, log scale), 2 cores")
        ax.set_ylabel("median per-pixel log-space RMSE")
        ax.set_title(f"field of view {fov} deg, {a.size} x {a.size} card, n = k = 20")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "tradeoffs.png"), dpi=100)
    print(f"wrote {a.out}/tradeoffs.csv and tradeoffs.png")


if __name__ == "__main__":
    main()
