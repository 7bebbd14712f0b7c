"""hapstate.Catalogue against an independent reader: Python's sqlite3, h5py and hapstate-inspect."""

import json
import sqlite3
import subprocess

import h5py
import numpy as np
import pytest

import hapstate
from conftest import TOOLS
from h5py_vectors import vector  # tests/blobs: the foreign reader of a segment


def rows(state, sql):
    with sqlite3.connect(f"file:{state.dir / 'catalogue.sqlite'}?mode=ro", uri=True) as db:
        return db.execute(sql).fetchall()


def test_configurations_equal_the_catalogue_rows(state):
    got = hapstate.Catalogue(state.dir).configurations()
    want = rows(state, "SELECT c.id, c.checkpoint, p.i, p.j, p.k, c.level, c.wave, c.expandable, "
                       "c.status, c.force_x, c.force_y, c.force_z, c.k_xx, c.k_xy, c.k_xz, c.k_yx, "
                       "c.k_yy, c.k_yz, c.k_zx, c.k_zy, c.k_zz, c.blob_name FROM configuration c "
                       "JOIN checkpoint p ON p.id = c.checkpoint ORDER BY c.id")
    assert len(got["id"]) == len(want) > 0
    for n, name in enumerate(["id", "checkpoint", "i", "j", "k", "level", "wave"]):
        assert got[name].tolist() == [r[n] for r in want], name
    assert got["expandable"].tolist() == [bool(r[7]) for r in want]
    assert got["status"].tolist() == [r[8] for r in want]
    assert got["force"].tolist() == [list(r[9:12]) for r in want]
    assert got["stiffness"].reshape(-1, 9).tolist() == [list(r[12:21]) for r in want]
    assert got["blob_name"] == [r[21] or "" for r in want]


def test_transitions_equal_the_catalogue_rows(state):
    got = hapstate.Catalogue(state.dir).transitions()
    want = rows(state, "SELECT source, direction, outcome, target, substeps, newton_iterations, "
                       "wall_ms, failure_reason, midpoint_fx FROM transition "
                       "ORDER BY source, direction")
    assert len(got["source"]) == len(want) > 0
    for n, name in enumerate(["source", "direction", "outcome"]):
        assert got[name].tolist() == [r[n] for r in want], name
    assert got["target"].tolist() == [-1 if r[3] is None else r[3] for r in want]
    assert got["wall_ms"].tolist() == [r[6] for r in want]
    assert got["failure_reason"] == [r[7] for r in want]
    mid = got["midpoint_force"][:, 0]
    assert [None if np.isnan(x) else x for x in mid] == [r[8] for r in want]


def test_summary_is_inspect_json(state):
    tool = subprocess.run([TOOLS / "hapstate-inspect", "--state", state.dir, "summary", "--json"],
                          check=True, capture_output=True, text=True)
    want = json.loads(tool.stdout)
    got = hapstate.Catalogue(state.dir).summary()
    assert got == want


def test_vectors_are_the_blobs(state):
    cat = hapstate.Catalogue(state.dir)
    c = cat.configurations()
    stored = [n for n, s in enumerate(c["blob_segment"]) if s > 0]
    n = stored[len(stored) // 2]
    v = cat.vectors(int(c["id"][n]))
    segment = state.dir / "blobs" / f"seg-{c['blob_segment'][n]:06d}.h5"
    with h5py.File(segment, "r") as f:
        u = vector(f, c["blob_name"][n], "u").astype(float)
        slopes = vector(f, c["blob_name"][n], "du_dp").astype(float)
    assert v["u"].shape == (u.size // 3, 3)
    assert np.array_equal(v["u"].ravel(), u.ravel())
    assert v["du_dp"].shape == (3, u.size // 3, 3)
    assert np.array_equal(v["du_dp"].ravel(), slopes.ravel())
    zero = [n for n, s in enumerate(c["blob_segment"]) if s < 0]
    if zero:
        assert np.all(cat.vectors(int(c["id"][zero[0]]))["u"] == 0)  # no gravity: u = 0


def test_query_and_errors(grab_state, tmp_path):
    cat = hapstate.Catalogue(grab_state.dir)
    q = cat.query("SELECT count(*) AS n, max(level) AS top FROM configuration")
    assert q["n"].tolist() == [len(cat.configurations()["id"])]
    with pytest.raises(hapstate.InputError):
        cat.query("DELETE FROM configuration")
    assert len(cat.configurations()["id"]) == q["n"][0]
    with pytest.raises(hapstate.InputError, match="no configuration with id 999999"):
        cat.vectors(999999)
    tool = subprocess.run([TOOLS / "hapstate-inspect", "--state", tmp_path / "nowhere", "summary"],
                          capture_output=True, text=True)
    with pytest.raises(hapstate.InputError) as e:
        hapstate.Catalogue(tmp_path / "nowhere")
    assert str(e.value) in tool.stderr


def test_solve_equals_eval_exact_forces(state):
    e = state.eval
    r = hapstate.solve(state.scene, e.path[:12], stiffness=True)
    assert r["converged"].all()
    assert np.abs(r["force"] - e.exact[:12]).max() <= 1e-9 * e.largest
    assert r["stiffness"].shape == (12, 3, 3)
    assert r["displacements"].shape[0] == 12 and r["displacements"].shape[2] == 3
    with pytest.raises(hapstate.InputError, match="nothing.toml"):
        hapstate.solve(state.scene.parent / "nothing.toml", e.path[:2])
