#!/usr/bin/python3
"""Throughput of the per-pixel reconstruction (issue 7): `acq reconstruct synthetic` against a
straightforward vectorised numpy implementation of the same solve on the same observations
(dumped by acq), and against bounds estimated for this machine. Prints megapixels per second
and writes out/bench/reconstruction/{throughput.csv,throughput.png}.

  /usr/bin/python3 tools/bench_reconstruction.py [--size 256] [--build build]

n = 20 views (the seed's directions), k = 20, three channels, nearest rows, 4 degree field of
view. Ours in each of its kernels (float64 SIMD lanes, the default; float32 lanes; one pixel at a
time with Eigen) and with rows shared by 8 x 8 tiles, each the median of three runs. The numpy version computes what ours does: per-pixel Rusinkiewicz bins, rows, mean,
reference and cos weight, the log mapping, the normal matrices, their eigenvalues (condition
number) and the ridge solve; its coefficients are checked against ours."""
import argparse
import csv
import os
import time

import numpy as np

from synthetic_reconstruction import acq_from, add_common_options, reconstruct
EPS = 1e-3


def read_basis(path):
    head = np.fromfile(path, np.uint32, 10)
    k_all, m = int(head[7]), int(head[8])
    off = np.fromfile(path, np.uint64, 7, offset=56)
    p = 90 * 90 * 180
    valid = np.memmap(path, np.uint8, "r", offset=int(off[0]), shape=(p,))
    ref = np.memmap(path, np.float32, "r", offset=int(off[1]), shape=(p,))
    mean = np.memmap(path, np.float32, "r", offset=int(off[2]), shape=(p,))
    q = np.memmap(path, np.float32, "r", offset=int(off[4]), shape=(p, k_all))
    return valid, ref, mean, q


def merl_bins(light, camera):
    """The MERL grid bin (nearest, as `--lookup nearest`) of each light/camera pair (... x 3)."""
    half = light + camera
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    sin_h = np.hypot(half[..., 0], half[..., 1])
    theta_h = np.arctan2(sin_h, half[..., 2])
    pole = sin_h < 1e-12
    cos_p = np.where(pole, 1.0, half[..., 0] / np.where(pole, 1, sin_h))
    sin_p = np.where(pole, 0.0, half[..., 1] / np.where(pole, 1, sin_h))
    x1 = cos_p * light[..., 0] + sin_p * light[..., 1]
    y1 = -sin_p * light[..., 0] + cos_p * light[..., 1]
    dx = half[..., 2] * x1 - sin_h * light[..., 2]
    dz = sin_h * x1 + half[..., 2] * light[..., 2]
    theta_d = np.arctan2(np.hypot(dx, y1), dz)
    phi_d = np.arctan2(y1, dx)
    phi_d = np.where(phi_d < -1e-9 * np.pi / 180, phi_d + np.pi, np.maximum(phi_d, 0))
    ih = np.clip((np.sqrt(theta_h / (np.pi / 2)) * 90 + 1e-9).astype(int), 0, 89)
    idd = np.clip((theta_d / (np.pi / 2) * 90 + 1e-9).astype(int), 0, 89)
    ip = np.clip((phi_d / np.pi * 180 + 1e-9).astype(int), 0, 179)
    return ip + 180 * idd + 16200 * ih


def numpy_solve(light, camera, rgb, basis, k, eta):
    valid, ref, mean, q = basis
    bins = merl_bins(light, camera)
    ok = (light[..., 2] > 0) & (camera[..., 2] > 0) & np.isfinite(rgb).all(-1) & (valid[bins] > 0)
    rows = np.where(ok[..., None], q[bins, :k].astype(np.float64), 0.0)  # P x V x k
    cosw = np.clip(light[..., 2] * camera[..., 2], 0.01, 1.0)[..., None]
    y = np.log((np.maximum(np.nan_to_num(rgb), 0) * cosw + EPS) / (ref[bins][..., None] + EPS))
    y = np.where(ok[..., None], y - mean[bins][..., None], 0.0)  # P x V x 3
    normal = np.einsum("pvk,pvj->pkj", rows, rows)
    ev = np.linalg.eigvalsh(normal)
    cond = np.sqrt(ev[:, -1] / np.maximum(ev[:, 0], 1e-300))
    normal += eta * np.eye(k)
    coeff = np.linalg.solve(normal, np.einsum("pvk,pvc->pkc", rows, y))  # P x k x 3
    return coeff.transpose(0, 2, 1), cond


def gemm_rate(dtype):
    a = np.random.rand(2000, 2000).astype(dtype)
    a @ a
    t = time.perf_counter()
    for _ in range(3):
        a @ a
    return 3 * 2 * 2000**3 / (time.perf_counter() - t)


def bounds():
    """Achievable float64 and float32 GEMM rates and memory bandwidth on this machine, measured
    with numpy."""
    flops = gemm_rate(np.float64), gemm_rate(np.float32)
    big = np.ones(50_000_000)
    dst = np.zeros_like(big)  # touched first, so the timing sees copies, not page faults
    t = time.perf_counter()
    for _ in range(3):
        np.copyto(dst, big)
    bandwidth = 3 * 2 * big.nbytes / (time.perf_counter() - t)  # read + write
    return flops, bandwidth


def main():
    ap = argparse.ArgumentParser()
    add_common_options(ap, 512)
    a = ap.parse_args()
    acq = acq_from(a)
    dump = os.path.join(a.out, "dump")
    def median_time(extra):
        return float(np.median([reconstruct(acq, a.basis, a.size, 4, os.path.join(a.out, "map.exr"),
                                            extra)[0] for _ in range(3)]))
    reconstruct(acq, a.basis, a.size, 4, os.path.join(a.out, "map.exr"),
                ["--row-tile", "1", "--dump", dump])
    meta = dict(line.split() for line in open(os.path.join(dump, "dump.txt")))
    pixels, views, k, eta = int(meta["pixels"]), int(meta["views"]), int(meta["k"]), float(meta["eta"])
    light = np.fromfile(os.path.join(dump, "light.f32"), np.float32).reshape(pixels, views, 3).astype(np.float64)
    camera = np.fromfile(os.path.join(dump, "camera.f32"), np.float32).reshape(pixels, views, 3).astype(np.float64)
    rgb = np.fromfile(os.path.join(dump, "rgb.f32"), np.float32).reshape(pixels, views, 3).astype(np.float64)
    ours = np.fromfile(os.path.join(dump, "coefficients.f32"), np.float32).reshape(pixels, 3, k)
    basis = read_basis(a.basis)
    t = time.perf_counter()
    coeff, _ = numpy_solve(light, camera, rgb, basis, k, eta)
    numpy_s = time.perf_counter() - t
    # Same answer? Relative difference of coefficient vectors (float32 storage on our side).
    diff = np.linalg.norm(coeff - ours, axis=-1) / np.maximum(np.linalg.norm(ours, axis=-1), 1e-12)
    ours_s = median_time(["--row-tile", "1"])
    single_s = median_time(["--row-tile", "1", "--kernel", "lanes-single"])
    one_pixel_s = median_time(["--row-tile", "1", "--kernel", "one-pixel"])
    # The same scene with rows shared by 8 x 8 tiles (one factorisation a tile).
    tiled_s = median_time(["--row-tile", "8"])
    (flops, flops32), bandwidth = bounds()
    # Arithmetic per pixel: normal matrix n k^2, the condition number (Cholesky k^3/3, then power
    # and inverse iteration warm-started from the previous pixel: 6.4 to 6.8 steps a pixel on
    # average, measured over 512 x 512 pixels at 4 and 10 degrees, each step k^2), the ridge
    # Cholesky k^3/3, right-hand sides 2 n k 3, solves 2 k^2 3; counted as multiply-adds x 2.
    # Memory per pixel: observations (9 floats a view) in, the gathered rows (k floats a view,
    # mostly cache misses), coefficients and 4 diagnostics out.
    condition_k2 = 6.8
    flop_px = 2 * (views * k * k + k**3 / 3 + condition_k2 * k * k + k**3 / 3
                   + 2 * views * k * 3 + 2 * k * k * 3)
    bytes_px = 4 * (9 * views + k * views + 3 * k + 4)
    mp = pixels / 1e6
    rows = [("acq, rows per pixel, float64 lanes", mp / ours_s),
            ("acq, rows per pixel, float32 lanes", mp / single_s),
            ("acq, rows per pixel, one at a time", mp / one_pixel_s),
            ("acq, rows per 8x8 tile", mp / tiled_s),
            ("numpy (vectorised)", mp / numpy_s),
            ("arithmetic bound, float64", flops / flop_px / 1e6),
            ("arithmetic bound, float32", flops32 / flop_px / 1e6),
            ("memory bound", bandwidth / bytes_px / 1e6)]
    value = dict(rows)
    print(f"{pixels} pixels, {views} views, k = {k}: coefficient agreement with numpy: median "
          f"{np.median(diff):.2e}, 99th percentile {np.percentile(diff, 99):.2e}")
    print(f"measured machine: {flops / 1e9:.1f} GFLOP/s float64 GEMM, {flops32 / 1e9:.1f} float32; "
          f"{bandwidth / 1e9:.1f} GB/s (copy)")
    print(f"per pixel: {flop_px / 1e3:.1f} kflop, {bytes_px / 1e3:.2f} kB")
    for name, v in rows:
        print(f"{name:<36} {v:8.3f} megapixels/s")
    ours = value["acq, rows per pixel, float64 lanes"]
    bound = min(value["arithmetic bound, float64"], value["memory bound"])
    bound32 = min(value["arithmetic bound, float32"], value["memory bound"])
    print(f"acq per pixel (float64 lanes) / numpy: {ours / value['numpy (vectorised)']:.1f}x; "
          f"{bound / ours:.1f}x below the tighter float64 bound; float32 lanes "
          f"{bound32 / value['acq, rows per pixel, float32 lanes']:.1f}x below the float32 bound "
          f"(bounds are for per-pixel work; tiles do less work a pixel)")
    with open(os.path.join(a.out, "throughput.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["implementation", "megapixels_per_s"])
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.6))
    ax.barh([r[0] for r in rows][::-1], [r[1] for r in rows][::-1],
            color=(["tab:red"] * 4 + ["tab:gray"] + ["tab:blue"] * 3)[::-1])
    ax.set_xscale("log")
    ax.set_xlabel("megapixels per second (log scale)")
    ax.set_title(f"Per-pixel reconstruction, n = {views}, k = {k}, 3 channels, 2 cores")
    for i, r in enumerate(rows[::-1]):
        ax.text(r[1], i, f" {r[1]:.3g}", va="center")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "throughput.png"), dpi=100)
    print(f"wrote {a.out}/throughput.csv and throughput.png")


if __name__ == "__main__":
    main()
