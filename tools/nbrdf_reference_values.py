#!/usr/bin/python3
"""Independent numpy evaluation of a neural-BRDF fit at a few angles, for the C++ unit test
(tests/test_neural_brdf.cpp). Follows data/nbrdf/README.md literally; run with Debian's python3.
usage: tools/nbrdf_reference_values.py data/nbrdf/merl/alum-bronze.h5"""
import sys
import h5py
import numpy as np

ANGLES_DEG = [(0.0, 0.0, 0.0), (10.0, 30.0, 45.0), (45.0, 60.0, 170.0), (2.5, 80.0, 90.0)]

with h5py.File(sys.argv[1], "r") as f:
    layers = [(np.array(f[f"dense_{i}/dense_{i}/kernel:0"], dtype=np.float64),
               np.array(f[f"dense_{i}/dense_{i}/bias:0"], dtype=np.float64)) for i in (1, 2, 3)]

for th, td, pd in ANGLES_DEG:
    th, td, pd = np.radians([th, td, pd])
    x = np.array([np.sin(th), 0.0, np.cos(th),
                  np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)])
    for i, (w, b) in enumerate(layers):
        x = x @ w + b
        if i < 2:
            x = np.maximum(x, 0.0)
    rgb = np.exp(x) - 1.0
    print(f"{{{np.degrees(th):g}, {np.degrees(td):g}, {np.degrees(pd):g}, "
          f"{rgb[0]:.9g}, {rgb[1]:.9g}, {rgb[2]:.9g}}},")
