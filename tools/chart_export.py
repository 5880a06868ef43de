#!/usr/bin/env python3
"""Charts and pictures of the export study (tools/study_export.sh; docs/export.md).

  chart_export.py fit FIT_JSON OUT.png         per material: the fit's median error; per
                                               validation view: the map's and the fitted maps'
                                               relative RMS against the capture
  chart_export.py side A.exr B.exr ... OUT.png the renders side by side as one sRGB PNG (one
                                               exposure for all: the 99th percentile of the first
                                               at 0.9)
  chart_export.py compare A.exr B.exr          relative RMS of A against B
  chart_export.py scaled A.exr B.exr OUT.exr   A times the least-squares scale onto B (a
                                               renderer whose light is in other units), that
                                               scale and the relative RMS after it
Run with the project's .venv python (Mitsuba reads the EXRs, matplotlib is Debian's).
"""
import json
import os
import sys

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so")


def read(path):
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path))[..., :3].astype(np.float64)


def chart_fit(fit_json, out):
    sys.path.insert(0, "/usr/lib/python3/dist-packages")  # Debian's matplotlib
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(fit_json) as f:
        fit = json.load(f)
    classes = fit.get("by_material") or fit.get("by_group") or []
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    ax = axes[0]
    ax.bar([c["name"] for c in classes], [c["median_log_rmse"] for c in classes], color="#4c72b0")
    ax.set_ylabel("median fit error (log-space RMS)")
    ax.set_title("Lambert + GGX against the measured map, per material")
    ax.tick_params(axis="x", rotation=20)
    ax = axes[1]
    views = fit.get("validation", [])
    x = range(len(views))
    ax.bar([i - 0.2 for i in x], [v["map_relative_rms"] for v in views], 0.4, label="measured map")
    ax.bar([i + 0.2 for i in x], [v["fitted_relative_rms"] for v in views], 0.4, label="fitted maps")
    ax.set_xticks(list(x), [v["view"].split(":")[-1] for v in views])
    ax.set_xlabel("validation view (line of validation_3.tsv)")
    ax.set_ylabel("relative RMS against the capture")
    ax.set_title("validation views never used to reconstruct")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


def side_by_side(paths, out):
    import mitsuba as mi
    import numpy as np
    images = [read(p) for p in paths]
    scale = 0.9 / max(np.percentile(images[0], 99), 1e-12)
    gap = np.ones((images[0].shape[0], 4, 3))
    row = []
    for i, im in enumerate(images):
        row += [im * scale] + ([gap] if i + 1 < len(images) else [])
    linear = np.clip(np.concatenate(row, axis=1), 0, 1)
    srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    mi.Bitmap((srgb * 255 + 0.5).astype(np.uint8), mi.Bitmap.PixelFormat.RGB).write(out)
    print(f"wrote {out}")


def compare(a, b):
    import numpy as np
    x, y = read(a), read(b)
    print(f"{np.sqrt(((x - y) ** 2).sum() / (y ** 2).sum()):.5f}")


def scaled(a, b, out):
    import mitsuba as mi
    import numpy as np
    x, y = read(a), read(b)
    k = (x * y).sum() / max((x * x).sum(), 1e-300)
    mi.Bitmap((x * k).astype(np.float32)).write(out)
    print(f"scale {k:.6g}, relative RMS after it {np.sqrt(((k * x - y) ** 2).sum() / (y ** 2).sum()):.5f}")


if __name__ == "__main__":
    if sys.argv[1] == "scaled":
        scaled(sys.argv[2], sys.argv[3], sys.argv[4])
    elif sys.argv[1] == "fit":
        chart_fit(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "side":
        side_by_side(sys.argv[2:-1], sys.argv[-1])
    else:
        compare(sys.argv[2], sys.argv[3])
