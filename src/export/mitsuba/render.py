#!/usr/bin/env python3
"""Renders an `acq export mitsuba` folder with Mitsuba 3 (docs/export.md).

The scene is the instrument's: the sample a quad in z = 0 (millimetres, centred), a point light
at the light arm's pose and a pinhole camera at the camera arm's, as scene.json states; the
point light's intensity makes a pixel's value rho cos(theta_i) / r^2 with r in metres, as
`acq render view` computes it. With the camera overhead (the reference view) the image is in
the map's pixels (the map's rows run along the sample's -y: core/sample_grid.h).

  python render.py [--spp 4] [-o render.exr] [--variant llvm_ad_rgb] [--fitted PBR_DIR]

--fitted renders the analytic maps `acq export pbr` fitted to the same map (PBR_DIR) with
Mitsuba's own principled BSDF instead of the plugin, to compare like with like: base colour and
roughness per texel; one specular level for the whole sample (the principled BSDF's `specular`
is a number, not a texture: the fit's median F0, as specular = F0 / 0.08).

Mitsuba 3.9's llvm variants need LLVM 19 (Debian's libllvm19); DRJIT_LIBLLVM_PATH is set to it
when it is not set already.
"""

import argparse
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
for candidate in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/llvm-19/lib/libLLVM-19.so"):
    if os.path.exists(candidate):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", candidate)
        break


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def principled(mi, pbr_dir):
    """Mitsuba's principled BSDF from an `acq export pbr` folder's textures."""
    with open(os.path.join(pbr_dir, "fit.json")) as f:
        fit = json.load(f)
    # The rectangle's v grows along +y; the textures' rows run along -y: v flipped.
    rows_down = mi.ScalarTransform4f().translate([0, 1, 0]).scale([1, -1, 1])
    texture = lambda name, raw: {"type": "bitmap", "filename": os.path.join(pbr_dir, name),
                                 "raw": raw, "filter_type": "nearest", "wrap_mode": "clamp",
                                 "to_uv": rows_down}
    return {"type": "principled", "base_color": texture("basecolor.png", False),
            "roughness": texture("roughness.png", True), "metallic": 0.0,
            "specular": min(max(fit["median_f0"] / 0.08, 0.0), 1.0)}


def scene_dict(mi, d, description, spp, bsdf=None):
    w, h, px = d["width"], d["height"], d["pixel_size_mm"]
    cam = d["camera"]
    eye = [cam["distance_mm"] * v for v in direction(cam["theta_deg"], cam["phi_deg"])]
    light = [d["light"]["distance_mm"] * v for v in direction(d["light"]["theta_deg"],
                                                               d["light"]["phi_deg"])]
    # Overhead, +y up in the image (the map's row 0 on top). Tilted, any up that is not along
    # the view.
    up = [0, 1, 0] if abs(eye[0]) < 1e-9 and abs(eye[1]) < 1e-9 else [0, 0, 1]
    fov = math.degrees(2 * math.atan(w * px / 2 / cam["distance_mm"]))
    return {
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {
            "type": "perspective",
            "fov_axis": "x",
            "fov": fov,
            "near_clip": 1.0,
            "far_clip": 10 * cam["distance_mm"],
            "to_world": mi.ScalarTransform4f().look_at(origin=eye, target=[0, 0, 0], up=up),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
        },
        # Intensity 1e6: a light of unit intensity with r in metres (1 m = 1000 mm).
        "light": {"type": "point", "position": light,
                  "intensity": {"type": "rgb", "value": [1e6, 1e6, 1e6]}},
        "sample": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f().scale([w * px / 2, h * px / 2, 1]),
            "bsdf": bsdf or {"type": "acq_svbrdf", "description": description},
        },
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=4, help="samples per pixel (default 4)")
    parser.add_argument("-o", "--output", default=os.path.join(HERE, "render.exr"))
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--description", default=os.path.join(HERE, "scene.json"))
    parser.add_argument("--fitted", help="an acq export pbr folder: render its maps instead")
    args = parser.parse_args()
    try:
        import mitsuba as mi
    except ImportError as e:
        sys.exit(f"render.py: Mitsuba 3 is not installed here ({e}); run tools/setup.sh and use "
                 "its .venv/bin/python")
    mi.set_variant(args.variant)
    sys.path.insert(0, HERE)
    import acq_svbrdf
    acq_svbrdf.register()
    with open(args.description) as f:
        d = json.load(f)
    start = time.time()
    bsdf = principled(mi, args.fitted) if args.fitted else None
    scene = mi.load_dict(scene_dict(mi, d, args.description, args.spp, bsdf))
    image = mi.render(scene)
    import numpy as np
    mi.Bitmap(np.ascontiguousarray(np.array(image))).write(args.output)
    print(f"wrote {args.output} ({d['width']} x {d['height']}, {args.spp} spp, "
          f"{time.time() - start:.1f} s)")


if __name__ == "__main__":
    main()
