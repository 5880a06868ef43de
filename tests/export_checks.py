#!/usr/bin/env python3
"""The export test's checks that need the renderers' Python tools (.venv): run by test_export.sh.

  export_checks.py pbr DIR             MaterialX validation of DIR/material.mtlx; the fit error
                                       map finite, the converged plane 0/1, fit.json consistent;
                                       the glTF quad's orientation (not mirrored, facing +Y)
  export_checks.py mitsuba DIR TOL     DIR/render.py's render against DIR/ours.exr (acq render
                                       view): relative RMS under TOL
"""
import json
import os
import subprocess
import sys

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so")


def read_exr(path):
    import mitsuba as mi
    import numpy as np
    mi.set_variant("scalar_rgb")
    bitmap = mi.Bitmap(path)
    return np.array(bitmap), [c for c in bitmap.struct_()]


def check_pbr(folder):
    import MaterialX as mx
    import numpy as np
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, os.path.join(folder, "material.mtlx"))
    libraries = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), libraries)
    doc.importLibrary(libraries)
    valid, message = doc.validate()
    if not valid:
        sys.exit(f"material.mtlx does not validate: {message}")
    materials = [m.getName() for m in doc.getMaterialNodes()]
    if len(materials) != 1:
        sys.exit(f"material.mtlx: {len(materials)} materials, expected 1")
    pixels, _ = read_exr(os.path.join(folder, "fit_error.exr"))
    if not np.all(np.isfinite(pixels)):
        sys.exit("fit_error.exr holds non-finite values")
    with open(os.path.join(folder, "fit.json")) as f:
        report = json.load(f)
    if not (0 <= report["median_log_rmse"] < 10) or report["pixels"] != pixels.shape[0] * pixels.shape[1]:
        sys.exit(f"fit.json inconsistent: {report}")
    check_gltf_orientation(folder)
    print(f"MaterialX: valid ({materials[0]}); fit error median {report['median_log_rmse']:.3f}, "
          f"{report['not_converged']} not converged; glTF quad not mirrored, facing +Y")


def gltf_accessor(gltf, buffer, index):
    import numpy as np
    accessor = gltf["accessors"][index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    dtype, width = {5126: (np.float32, 4), 5123: (np.uint16, 2)}[accessor["componentType"]]
    n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[accessor["type"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    return np.frombuffer(buffer, dtype, accessor["count"] * n, start).reshape(-1, n)


def check_gltf_orientation(folder):
    """The map's first texel (its top-left: the sample's -x, +y as the reference camera sees it)
    must lie at glTF's -X, -Z (the sample's y is glTF's -Z), and every triangle face +Y: else a
    renderer shows the sample mirrored (Blender's import of the first export did)."""
    import numpy as np
    with open(os.path.join(folder, "material.gltf")) as f:
        gltf = json.load(f)
    with open(os.path.join(folder, gltf["buffers"][0]["uri"]), "rb") as f:
        buffer = f.read()
    primitive = gltf["meshes"][0]["primitives"][0]
    position = gltf_accessor(gltf, buffer, primitive["attributes"]["POSITION"])
    uv = gltf_accessor(gltf, buffer, primitive["attributes"]["TEXCOORD_0"])
    indices = gltf_accessor(gltf, buffer, primitive["indices"]).reshape(-1, 3)
    corner = position[np.argmin(uv[:, 0] + uv[:, 1])]
    if not (corner[0] < 0 and corner[2] < 0):
        sys.exit(f"material.gltf: the texture's top-left corner lies at {corner}, expected -X, -Z")
    for a, b, c in indices:
        facing = np.cross(position[b] - position[a], position[c] - position[a])
        if not facing[1] > 0:
            sys.exit(f"material.gltf: triangle {a} {b} {c} faces {facing}, expected +Y")


def check_mitsuba(folder, tolerance):
    import numpy as np
    render = os.path.join(folder, "render.exr")
    out = subprocess.run([sys.executable, os.path.join(folder, "render.py"), "--spp", "4", "-o", render],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"render.py failed: {out.stderr[-2000:]}")
    theirs, _ = read_exr(render)
    ours, _ = read_exr(os.path.join(folder, "ours.exr"))
    theirs, ours = theirs[..., :3], ours[..., :3]
    if theirs.shape != ours.shape:
        sys.exit(f"render {theirs.shape} against ours {ours.shape}")
    rel = float(np.sqrt(((theirs - ours) ** 2).sum() / (ours ** 2).sum()))
    print(f"{out.stdout.strip()}; relative RMS against acq render view {rel:.4f}")
    if not rel < tolerance:
        sys.exit(f"relative RMS {rel:.4f} is not under {tolerance}")


if __name__ == "__main__":
    if sys.argv[1] == "pbr":
        check_pbr(sys.argv[2])
    else:
        check_mitsuba(sys.argv[2], float(sys.argv[3]))
