#!/usr/bin/python3
"""A straightforward numpy implementation of the basis build (docs/architecture.md, "The method
in one page"), kept as the independent reference that `acq basis build` is checked and benchmarked
against. Run with Debian's python3 (numpy, h5py).

  tools/reference_basis.py data/nbrdf/merl [--holdout-every 10 --holdout-offset 5]
                           [--directions data/directions/seed_directions_20.tsv --k 20 --eta 40]

Builds the basis from every material not held out (full SVD of the centred float64 matrix),
and with --directions reconstructs the held-out materials and prints the median errors."""
import argparse
import os
import time

import h5py
import numpy as np

EPS = 1e-3
COSW_MIN = 0.01


def grid():
    """Bin centres (midpoints), directions, horizon mask and cos weight for all 1458000 bins."""
    ih, idd, ip = np.meshgrid(np.arange(90), np.arange(90), np.arange(180), indexing="ij")
    th = ((ih + 0.5) / 90) ** 2 * np.pi / 2
    td = (idd + 0.5) * np.pi / 180
    pd = (ip + 0.5) * np.pi / 180
    th, td, pd = th.ravel(), td.ravel(), pd.ravel()
    d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)], axis=1)
    # Rotate the difference vector out of the half frame (phi_h = 0): about y by theta_h.
    c, s = np.cos(th), np.sin(th)
    wi_z = -s * d[:, 0] + c * d[:, 2]
    wo_z = s * d[:, 0] + c * d[:, 2]  # w_o = d reflected about the half vector
    valid = (wi_z > 0) & (wo_z > 0)
    cosw = np.clip(wi_z * wo_z, COSW_MIN, 1.0)
    inputs = np.stack([np.sin(th), np.zeros_like(th), np.cos(th), d[:, 0], d[:, 1], d[:, 2]], 1)
    return th, td, pd, valid, cosw, inputs


def tabulate(path, inputs):
    with h5py.File(path, "r") as f:
        x = inputs
        for i in (1, 2, 3):
            w = np.array(f[f"dense_{i}/dense_{i}/kernel:0"], dtype=np.float64)
            b = np.array(f[f"dense_{i}/dense_{i}/bias:0"], dtype=np.float64)
            x = x @ w + b
            if i < 3:
                x = np.maximum(x, 0)
    return np.maximum(np.expm1(x), 0).T  # 3 x n


def bin_index(th_deg, td_deg, pd_deg):
    th, td, pd = np.radians([th_deg, td_deg, pd_deg])
    ih = 0 if th <= 0 else min(int(np.sqrt(th / (np.pi / 2)) * 90), 89)
    idd = min(max(int(td / (np.pi / 2) * 90), 0), 89)
    if pd < 0:
        pd += np.pi
    ip = min(max(int(pd / np.pi * 180), 0), 179)
    return ip + 180 * idd + 180 * 90 * ih


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("materials")
    ap.add_argument("--holdout-every", type=int, default=0)
    ap.add_argument("--holdout-offset", type=int, default=0)
    ap.add_argument("--components", type=int, default=64)
    ap.add_argument("--directions")
    ap.add_argument("--k", type=int, default=20)
    ap.add_argument("--eta", type=float, default=40.0)
    a = ap.parse_args()

    t0 = time.time()
    names = sorted(n[:-3] for n in os.listdir(a.materials) if n.endswith(".h5"))
    held = [n for i, n in enumerate(names)
            if a.holdout_every and i % a.holdout_every == a.holdout_offset]
    train = [n for n in names if n not in held]
    th, td, pd, valid, cosw, inputs = grid()
    inputs_v, cosw_v = inputs[valid], cosw[valid]

    x = np.concatenate([tabulate(os.path.join(a.materials, n + ".h5"), inputs_v) for n in train])
    t_tab = time.time()
    weighted = x * cosw_v
    ref = np.median(weighted, axis=0)
    y = np.log((weighted + EPS) / (ref + EPS))
    mu = y.mean(axis=0)
    u, s, vt = np.linalg.svd(y - mu, full_matrices=False)
    q = vt[: a.components].T * s[: a.components]  # components scaled by singular values
    t_end = time.time()
    print(f"reference: {len(train)} training materials, {x.shape[0]} rows, {x.shape[1]} valid bins")
    print(f"reference: tabulation {t_tab - t0:.1f} s, mapping+SVD {t_end - t_tab:.1f} s, "
          f"total {t_end - t0:.1f} s")
    print("reference: first singular values", " ".join(f"{v:.4g}" for v in s[:5]))

    if a.directions and held:
        rows = np.loadtxt(a.directions, comments="#", skiprows=0, dtype=str)
        rows = rows[1:].astype(float)  # drop the header line
        col_of_bin = -np.ones(valid.size, dtype=np.int64)
        col_of_bin[valid] = np.arange(valid.sum())
        cols = np.array([col_of_bin[bin_index(*r)] for r in rows])
        qs, mus = q[cols, : a.k], mu[cols]
        errs = []
        for n in held:
            truth = tabulate(os.path.join(a.materials, n + ".h5"), inputs_v)
            for ch in range(3):
                xt = np.log((truth[ch] * cosw_v + EPS) / (ref + EPS))
                c = np.linalg.solve(qs.T @ qs + a.eta * np.eye(a.k), qs.T @ (xt[cols] - mus))
                xr = q[:, : a.k] @ c + mu
                errs.append(np.sqrt(np.mean((xr - xt) ** 2)))
        print(f"reference: median log-space RMSE over {len(errs)} held-out channels: "
              f"{np.median(errs):.4f}")


if __name__ == "__main__":
    main()
