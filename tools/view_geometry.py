"""`acq render view`'s default geometry, shared by the scripts that render an export in other
renderers at the same light and camera: tools/render_blender.py (in Blender's own Python) and
tools/render_materialx.py (in .venv's). Plain Python, no imports beyond the standard library.
"""
import math

DISTANCE_M = 1.0  # acq render view: camera and light arms of 1000 mm


def add_arguments(parser):
    """The light's pose and the image's width, with `acq render view`'s defaults."""
    parser.add_argument("--light-theta-deg", type=float, default=30)
    parser.add_argument("--light-phi-deg", type=float, default=0)
    parser.add_argument("--width", type=int, default=256)


def light_position_m(theta_deg, phi_deg):
    """The light in the sample frame (z along the normal, x along gantry azimuth 0), metres."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [DISTANCE_M * math.sin(t) * math.cos(p), DISTANCE_M * math.sin(t) * math.sin(p),
            DISTANCE_M * math.cos(t)]
