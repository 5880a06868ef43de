#!/usr/bin/python3
"""Writes the small bad-input fixtures in tests/data (run with Debian's python3):
wrong_shapes.h5, a Keras-like fit whose hidden layer is 21 x 30 instead of 21 x 21."""
import os
import h5py
import numpy as np

out = os.path.join(os.path.dirname(__file__), "..", "tests", "data")
rng = np.random.default_rng(0)
shapes = {1: ((6, 21), (21,)), 2: ((21, 30), (30,)), 3: ((30, 3), (3,))}
with h5py.File(os.path.join(out, "wrong_shapes.h5"), "w") as f:
    for i, (k, b) in shapes.items():
        f[f"dense_{i}/dense_{i}/kernel:0"] = rng.standard_normal(k).astype(np.float32)
        f[f"dense_{i}/dense_{i}/bias:0"] = rng.standard_normal(b).astype(np.float32)
