#!/usr/bin/python3
"""Why a pooled group's centre trusts the plan's directions (issue 17; docs/reconstruction.md,
"Why the centres trust the plan's directions"): one material's centre fitted from a card's
pixels in different ways, each scored over the whole MERL grid against the truth, for every
held-out MERL material. Run with Debian's python3 (numpy, h5py) on acq's dump of a card seen
without noise, its observations read from the truth's tables:

  build/src/cli/acq reconstruct synthetic --basis out/main/basis116.acqb \\
      --directions out/main/optimized20.tsv --fov-deg 4 --size 64x64 --truth-tables \\
      --method independent -o /tmp/card.exr --dump /tmp/dump
  /usr/bin/python3 tools/study_design_weighting.py out/main/basis116.acqb /tmp/dump

Only the dump's directions are used (the same for every material); each material's observation
at a pixel and view is its table's value at that bin, as --truth-tables gives. Prints, per
material, the centre's log-space RMSE over the grid (k = 20, eta = 20, as the solve) when fitted
from: every grid bin (the best k components can do), the pixel at the field's centre, every
pixel alike, and pixels weighted by a Gaussian of their distance from the field's centre."""
import argparse
import os

import numpy as np

from bench_reconstruction import merl_bins, read_basis
from reference_basis import EPS, grid, tabulate

SIGMAS = (0.1, 0.25, 0.5, 1.0)  # Gaussian weights' widths, in half-fields


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("basis")
    ap.add_argument("dump")
    ap.add_argument("--materials-dir", default="data/nbrdf/merl")
    ap.add_argument("--k", type=int, default=20)
    ap.add_argument("--eta", type=float, default=20.0)
    a = ap.parse_args()
    valid, ref, mean, q = read_basis(a.basis)
    _, _, _, _, cosw, inputs = grid()
    vb = np.nonzero(valid)[0]
    q_valid = np.asarray(q[vb, : a.k], dtype=np.float64)
    meta = dict(line.split() for line in open(os.path.join(a.dump, "dump.txt")))
    pixels, views = int(meta["pixels"]), int(meta["views"])
    shape = (pixels, views, 3)
    light = np.fromfile(os.path.join(a.dump, "light.f32"), np.float32).reshape(shape)
    camera = np.fromfile(os.path.join(a.dump, "camera.f32"), np.float32).reshape(shape)
    at = np.searchsorted(vb, merl_bins(light.astype(np.float64), camera.astype(np.float64)))
    side = int(round(np.sqrt(pixels)))
    yy, xx = np.divmod(np.arange(pixels), side)
    radius = np.hypot(xx - side / 2 + 0.5, yy - side / 2 + 0.5) / (side / 2)
    centre = (side // 2) * side + side // 2
    rows = [q_valid[at[:, v]] for v in range(views)]  # per view: pixels x k

    def fit(truth, weights):  # the weighted mean of the pixels' normal equations, ridge eta
        lhs, rhs = np.zeros((a.k, a.k)), np.zeros((a.k, 3))
        for v in range(views):
            lhs += (rows[v] * weights[:, None]).T @ rows[v]
            rhs += (rows[v] * weights[:, None]).T @ truth[:, at[:, v]].T
        return np.linalg.solve(lhs / weights.sum() + a.eta * np.eye(a.k), rhs / weights.sum())

    names = sorted(f[:-3] for f in os.listdir(a.materials_dir) if f.endswith(".h5"))[5::10]
    print("material                 every bin  centre px  alike   " +
          "  ".join(f"gauss {s:<4}" for s in SIGMAS))
    table = []
    for name in names:
        rho = tabulate(os.path.join(a.materials_dir, name + ".h5"), inputs[vb])
        truth = np.log((rho * cosw[vb] + EPS) / (ref[vb] + EPS)) - mean[vb]  # 3 x bins, mapped

        def error(c):
            return np.mean(np.sqrt(np.mean((q_valid @ c - truth.T) ** 2, axis=0)))

        best = np.linalg.lstsq(q_valid, truth.T, rcond=None)[0]
        row = [error(best), error(fit(truth, (np.arange(pixels) == centre) * 1.0)),
               error(fit(truth, np.ones(pixels)))]
        row += [error(fit(truth, np.exp(-0.5 * (radius / s) ** 2))) for s in SIGMAS]
        table.append(row)
        print(f"{name:24s} " + "  ".join(f"{x:9.3f}" for x in row))
    print(f"{'median':24s} " + "  ".join(f"{x:9.3f}" for x in np.median(table, axis=0)))


if __name__ == "__main__":
    main()
