#!/usr/bin/env python3
"""Charts and pictures of the export study (tools/study_export.sh; docs/export.md).

  chart_export.py fit FIT_JSON... OUT.png      per material: the fit's median error; per
                                               validation view: the map's and the fitted maps'
                                               relative RMS against the capture; the fit's time
                                               against its worst view; one bar per fit.json
                                               (one per model)
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


def fit_label(fit):
    return f"{fit.get('model', 'schlick')}, {fit.get('max_zenith_deg', 80):g} deg"


def chart_fit(fit_jsons, out):
    """One bar per fit.json (one per model) in each group; a third panel: time against error."""
    sys.path.insert(0, "/usr/lib/python3/dist-packages")  # Debian's matplotlib
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fits = []
    for path in fit_jsons:
        with open(path) as f:
            fits.append(json.load(f))
    width = 0.8 / (len(fits) + 1)
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.9))
    ax = axes[0]
    for i, fit in enumerate(fits):
        classes = fit.get("by_material") or fit.get("by_group") or []
        ax.bar([j + (i - len(fits) / 2) * width for j in range(len(classes))],
               [c["median_log_rmse"] for c in classes], width, label=fit_label(fit))
        ax.set_xticks(range(len(classes)), [c["name"] for c in classes], rotation=20)
    ax.set_ylabel("median fit error (log-space RMS)")
    ax.set_title("the fit against the measured map, per material")
    ax.legend()
    ax = axes[1]
    views = fits[0].get("validation", [])
    x = range(len(views))
    offset = -len(fits) / 2 * width
    ax.bar([i + offset for i in x], [v["map_relative_rms"] for v in views], width,
           label="measured map", color="#555555")
    for k, fit in enumerate(fits):
        ax.bar([i + offset + (k + 1) * width for i in x],
               [v["fitted_relative_rms"] for v in fit.get("validation", [])], width,
               label="fitted, " + fit_label(fit))
    ax.set_xticks(list(x), [v["view"].split(":")[-1] for v in views])
    ax.set_xlabel("validation view (line of validation_3.tsv)")
    ax.set_ylabel("relative RMS against the capture")
    ax.set_title("validation views never used to reconstruct")
    ax.legend(fontsize=8)
    ax = axes[2]
    for i, fit in enumerate(fits):
        ratios = [v["ratio"] for v in fit.get("validation", [])]
        worst = max(ratios) if ratios else fit["median_log_rmse"]
        ax.scatter(fit["fit_seconds"], worst, s=40)
        # Alternately above and below: neighbouring models' labels would overlap.
        ax.annotate(fit_label(fit), (fit["fit_seconds"], worst), textcoords="offset points",
                    xytext=(5, 6 if i % 2 == 0 else -14))
    ax.axhline(1.5, color="#999999", linestyle="--", linewidth=1)
    ax.set_xlabel("time to fit the map (s, this machine)")
    ax.set_ylabel("worst validation view, fitted / measured")
    ax.set_title("speed against accuracy (goal 1.5x dashed)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
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
        chart_fit(sys.argv[2:-1], sys.argv[-1])
    elif sys.argv[1] == "side":
        side_by_side(sys.argv[2:-1], sys.argv[-1])
    else:
        compare(sys.argv[2], sys.argv[3])
