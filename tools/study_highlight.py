#!/usr/bin/python3
"""What limits the validation view nearest the highlight (issue 16; docs/colour.md, "The view
nearest the highlight"). On a simulated session's kept validation data
(renders/validation_NNN.exr, the light and camera directions at every map pixel) and its truth
labels (ground_truth/error.exr), every pixel is predicted by its true material's *homogeneous*
reconstruction: the material alone, at the sample's centre (no near field), without noise, from
the same basis and directions, by the default (pooled) reconstruction (`acq reconstruct
synthetic --fov-deg 0`: one group, whose centre is every pixel; its BRDF exported as a MERL
table). That is the floor the method itself sets at this view, before any near field,
noise or grouping: the basis's shape of each material's peak seen through 20 directions. Each
prediction is compared with the true material (the neural-BRDF fit, evaluated at the pixel's own
directions, not binned) in CIEDE2000 as the session's report does (linear Rec. 709 times pi,
D65 white at 1), per material; and the truth with the capture, as a check of the conversions.

Two steps, since the EXR reader is Mitsuba's (the renderers' environment) and h5py is Debian's:
  .venv/bin/python tools/study_highlight.py dump SESSION VIEW OUT_DIR
  /usr/bin/python3 tools/study_highlight.py floor OUT_DIR TABLES_DIR [--interpolated]
tools/study_highlight.sh runs both and makes the tables."""
import struct
import sys

import numpy as np

NAMES_FILE = "ground_truth/materials.tsv"


def dump(session, view, out):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    for name, path in [("view", f"{session}/renders/validation_{int(view):03d}.exr"),
                       ("truth", f"{session}/ground_truth/error.exr")]:
        bitmap = mi.Bitmap(path)
        planes = np.array(bitmap)
        names = [bitmap.struct_()[i].name for i in range(len(bitmap.struct_()))]
        np.savez(f"{out}/{name}.npz", **{n: planes[..., i] for i, n in enumerate(names)})


def rusinkiewicz(light, camera):
    """theta_h, theta_d, phi_d (radians) of unit direction rows."""
    h = light + camera
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    theta_h = np.arccos(np.clip(h[:, 2], -1, 1))
    phi_h = np.arctan2(h[:, 1], h[:, 0])
    c, s = np.cos(-phi_h), np.sin(-phi_h)
    x, y, z = c * light[:, 0] - s * light[:, 1], s * light[:, 0] + c * light[:, 1], light[:, 2]
    c, s = np.cos(-theta_h), np.sin(-theta_h)
    dx, dz = c * x + s * z, -s * x + c * z
    return theta_h, np.arccos(np.clip(dz, -1, 1)), np.arctan2(y, dx)


def neural_brdf(path, theta_h, theta_d, phi_d):
    """The material's network (reference_basis.tabulate) at the angles, R G B per row."""
    from reference_basis import tabulate
    inputs = np.stack([np.sin(theta_h), 0 * theta_h, np.cos(theta_h), np.sin(theta_d) * np.cos(phi_d),
                       np.sin(theta_d) * np.sin(phi_d), np.cos(theta_d)], 1)
    return tabulate(path, inputs).T


def merl_table(path):
    data = open(path, "rb").read()
    dims = struct.unpack("3i", data[:12])
    table = np.frombuffer(data[12:], dtype=np.float64).reshape(3, *dims)
    return table * np.array([1 / 1500, 1.15 / 1500, 1.66 / 1500])[:, None, None, None]


def merl_lookup(table, theta_h, theta_d, phi_d, interpolated):
    """MERL's bins; interpolated: linear in theta_h's bin index (the steep direction here)."""
    td = np.clip((theta_d / (np.pi / 2) * 90).astype(int), 0, 89)
    pd = np.clip((np.where(phi_d < 0, phi_d + np.pi, phi_d) / np.pi * 180).astype(int), 0, 179)
    u = np.sqrt(theta_h / (np.pi / 2)) * 90
    if not interpolated:
        return table[:, np.clip(u.astype(int), 0, 89), td, pd].T
    u = np.clip(u - 0.5, 0, 89)
    i0 = np.floor(u).astype(int)
    w = (u - i0)[:, None]
    return (1 - w) * table[:, i0, td, pd].T + w * table[:, np.minimum(i0 + 1, 89), td, pd].T


def lab(rgb):
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = rgb @ m.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]), 200 * (f[:, 1] - f[:, 2])], 1)


def delta_e2000(x, y):
    """Sharma, Wu and Dalal's formulation (src/core/colour.cpp's, in numpy)."""
    l1, a1, b1 = x.T
    l2, a2, b2 = y.T
    c_bar = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(c_bar ** 7 / (c_bar ** 7 + 25 ** 7)))
    a1, a2 = (1 + g) * a1, (1 + g) * a2
    c1, c2 = np.hypot(a1, b1), np.hypot(a2, b2)
    h1, h2 = np.degrees(np.arctan2(b1, a1)) % 360, np.degrees(np.arctan2(b2, a2)) % 360
    dh = h2 - h1
    dh = np.where(dh > 180, dh - 360, np.where(dh < -180, dh + 360, dh))
    dh = np.where(c1 * c2 == 0, 0, dh)
    d_l, d_c, d_h = l2 - l1, c2 - c1, 2 * np.sqrt(c1 * c2) * np.sin(np.radians(dh) / 2)
    l_bar, c_bar = (l1 + l2) / 2, (c1 + c2) / 2
    hs = h1 + h2
    h_bar = np.where(np.abs(h1 - h2) > 180, np.where(hs < 360, (hs + 360) / 2, (hs - 360) / 2), hs / 2)
    h_bar = np.where(c1 * c2 == 0, hs, h_bar)
    t = (1 - 0.17 * np.cos(np.radians(h_bar - 30)) + 0.24 * np.cos(np.radians(2 * h_bar))
         + 0.32 * np.cos(np.radians(3 * h_bar + 6)) - 0.20 * np.cos(np.radians(4 * h_bar - 63)))
    s_l = 1 + 0.015 * (l_bar - 50) ** 2 / np.sqrt(20 + (l_bar - 50) ** 2)
    s_c, s_h = 1 + 0.045 * c_bar, 1 + 0.015 * c_bar * t
    r_t = (-np.sin(np.radians(60 * np.exp(-((h_bar - 275) / 25) ** 2)))
           * 2 * np.sqrt(c_bar ** 7 / (c_bar ** 7 + 25 ** 7)))
    return np.sqrt((d_l / s_l) ** 2 + (d_c / s_c) ** 2 + (d_h / s_h) ** 2
                   + r_t * (d_c / s_c) * (d_h / s_h))


def floor(out, tables, interpolated, names):
    view, truth = np.load(f"{out}/view.npz"), np.load(f"{out}/truth.npz")
    light = np.stack([view[f"light.{c}"] for c in "xyz"], -1).reshape(-1, 3)
    camera = np.stack([view[f"camera.{c}"] for c in "xyz"], -1).reshape(-1, 3)
    captured = np.stack([view[f"captured.{c}"] for c in "RGB"], -1).reshape(-1, 3)
    label = truth["label"].round().astype(int).reshape(-1)
    compared = (view["compared"].reshape(-1) > 0.5) & np.all(np.isfinite(light + camera), 1)
    light[~compared], camera[~compared] = (0, 0, 1), (0, 0, 1)  # off the map: not compared
    angles = rusinkiewicz(light, camera)
    floor_de, capture_de = np.full(len(label), np.nan), np.full(len(label), np.nan)
    print("material        pixels  theta_h (deg)  homogeneous / truth, G: p10 / median / p90  "
          "CIEDE2000 median")
    for m, name in enumerate(names):
        sel = compared & (label == m)
        if not sel.any():
            continue
        a = [x[sel] for x in angles]
        cos_in = np.maximum(light[sel, 2], 0)[:, None]
        true = neural_brdf(f"data/nbrdf/merl/{name}.h5", *a) * cos_in
        homogeneous = merl_lookup(merl_table(f"{tables}/{name}.binary"), *a, interpolated) * cos_in
        floor_de[sel] = delta_e2000(lab(np.pi * true), lab(np.pi * homogeneous))
        capture_de[sel] = delta_e2000(lab(np.pi * true), lab(np.pi * captured[sel]))
        ratio = homogeneous[:, 1] / true[:, 1]
        print(f"{name:15s} {sel.sum():6d}  {np.degrees(a[0]).min():4.1f}-{np.degrees(a[0]).max():4.1f}"
              f"      {np.percentile(ratio, 10):.3f} / {np.median(ratio):.3f} / "
              f"{np.percentile(ratio, 90):.3f}                    {np.median(floor_de[sel]):.2f}")
    print(f"all pixels: the homogeneous reconstruction against the truth, median CIEDE2000 "
          f"{np.nanmedian(floor_de):.2f}; the truth against the capture {np.nanmedian(capture_de):.2f}")


if __name__ == "__main__":
    if len(sys.argv) >= 5 and sys.argv[1] == "dump":
        dump(*sys.argv[2:5])
    elif len(sys.argv) >= 4 and sys.argv[1] == "floor":
        names = [line.split("\t")[1].strip() for line in open(f"{sys.argv[2]}/materials.tsv")
                 if not line.startswith("#")]
        floor(sys.argv[2], sys.argv[3], "--interpolated" in sys.argv[4:], names)
    else:
        sys.exit(__doc__)
