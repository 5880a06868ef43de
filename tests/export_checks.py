#!/usr/bin/env python3
"""The export test's checks that need the renderers' Python tools (.venv): run by test_export.sh.

  export_checks.py pbr DIR             MaterialX validation of DIR/material.mtlx; the fit error
                                       map finite, the converged plane 0/1, fit.json consistent
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
    print(f"MaterialX: valid ({materials[0]}); fit error median {report['median_log_rmse']:.3f}, "
          f"{report['not_converged']} not converged")


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
