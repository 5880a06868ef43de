#!/usr/bin/python3
"""Accuracy against cost for the lens-model ladder (issue 4).

Synthesises boards seen by the example OPENCV8 camera (0.3 px noise, boards reaching into the
corners), solves them with each model of the ladder through `acq calibrate intrinsics`, and
prints and charts each model's projection error against the truth (mean-frames at the boards'
distance, as tools/compare_calibration.py) and its solve time. Then runs `--lensmodel auto` and
prints the table it decided from.

Usage: /usr/bin/python3 tools/bench_lensmodels.py [--build build] [--out out/bench/lensmodels]
"""
import argparse
import os
import re
import sys
import time

import numpy as np
import mrcal

sys.path.insert(0, os.path.dirname(__file__))
from compare_calibration import run, read_poses, read_corners, board_points, projection_error  # noqa: E402
import cv2  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default="out/bench/lensmodels")
    ap.add_argument("--n", type=int, default=40)
    a = ap.parse_args()
    acq = os.path.join(a.build, "src/cli/acq")
    os.makedirs(a.out, exist_ok=True)
    W, H, spacing = 10, 10, 25.0
    run([acq, "calibrate", "synthesize", "-o", a.out, "--n", str(a.n), "--noise-px", "0.3",
         "--partial-boards", "--centre-spread", "1.1", "--seed", "5"])
    truth = mrcal.cameramodel(os.path.join(a.out, "truth.cameramodel"))
    names, rt_truth = read_poses(os.path.join(a.out, "poses.tsv"))
    cache = os.path.join(a.out, "corners.vnl")
    corners = read_corners(cache, W, H)
    pts = board_points(W, H, spacing)
    distance = float(np.median([np.linalg.norm(mrcal.transform_point_rt(rt, pts.mean(axis=0))) for rt in rt_truth]))
    ladder = ["LENSMODEL_OPENCV4", "LENSMODEL_OPENCV5", "LENSMODEL_OPENCV8", "LENSMODEL_OPENCV12",
              "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=8_Ny=6_fov_x_deg=72",
              "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=72"]
    rows = []
    print(f"{'model':66s} {'params':>6s} {'solve s':>8s} {'err median':>10s} {'err p95':>8s} {'err max':>8s}")
    for i, model_name in enumerate(ladder):
        path = os.path.join(a.out, f"model-{i}.cameramodel")
        t0 = time.time()
        r = run([acq, "calibrate", "intrinsics", "--corners-cache", cache, "--board", f"{W}x{H}",
                 "--spacing-mm", str(spacing), "--imagersize", "1280,1024", "--lensmodel", model_name,
                 "--force", "-o", path])
        wall = time.time() - t0
        solve = float(re.search(r"solve ([0-9.]+) s", r.stdout).group(1))
        model = mrcal.cameramodel(path)
        rt_model = []
        for name in names:
            c = corners[name]
            ok = c[:, 2] > 0
            rays = mrcal.unproject(c[ok, :2], *model.intrinsics())
            _, rvec, tvec = cv2.solvePnP(pts[ok], (rays[:, :2] / rays[:, 2:]).astype(np.float64), np.eye(3), None)
            rt_model.append(np.concatenate([rvec.ravel(), tvec.ravel()]))
        e = projection_error(truth, model, rt_truth, rt_model, distance)
        nparams = len(model.intrinsics()[1])
        rows.append((model_name, nparams, solve, np.median(e), np.percentile(e, 95), e.max(), wall))
        print(f"{model_name:66s} {nparams:6d} {solve:8.2f} {np.median(e):10.4f} {np.percentile(e, 95):8.4f} {e.max():8.4f}")
    r = run([acq, "calibrate", "intrinsics", "--corners-cache", cache, "--board", f"{W}x{H}",
             "--spacing-mm", str(spacing), "--imagersize", "1280,1024", "--lensmodel", "auto",
             "--force", "-o", os.path.join(a.out, "auto.cameramodel")])
    print("\n`--lensmodel auto`:")
    print("\n".join(l for l in r.stdout.splitlines()[:8]))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for (name, n, solve, med, p95, mx, _) in rows:
            label = name.replace("LENSMODEL_", "").replace("SPLINED_STEREOGRAPHIC_order=3_", "spline ")
            ax.errorbar(solve, med, yerr=[[0], [p95 - med]], fmt="o", capsize=3)
            ax.annotate(f"{label} ({n})", (solve, med), textcoords="offset points", xytext=(5, 5), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("solve time, s (2-core machine)")
        ax.set_ylabel("projection error vs truth, px (median, bar to p95)")
        ax.set_title("Lens-model ladder: accuracy against cost (OPENCV8 truth, 0.3 px noise)")
        fig.tight_layout()
        out = os.path.join(a.out, "lensmodels.png")
        fig.savefig(out, dpi=120)
        print("chart:", out)
    except ImportError:
        print("matplotlib not installed: no chart")


if __name__ == "__main__":
    sys.exit(main())
