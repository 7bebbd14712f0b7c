"""hapstate.Playback and hapstate.Cursor against hapstate-eval (the C++ tool) and the file."""

import time

import numpy as np
import pytest

import hapstate


def test_cursor_force_equals_eval_columns(state):
    """Cursor.force along eval's path gives eval's played-back forces (CSV: 12 digits)."""
    pb = hapstate.Playback(state.dir / "playback.bin")
    e = state.eval
    for scheme, expected in (("hermite", e.hermite), ("trilinear", e.trilinear)):
        got = pb.cursor(scheme).force(e.path)
        assert got.shape == (len(e.path), 3)
        assert np.abs(got - expected).max() <= 1e-9 * e.largest, scheme


def test_cursor_continues_its_history(state):
    """Two calls over the halves of a path give what one call over the whole path gives."""
    pb = hapstate.Playback(state.dir)
    path = state.eval.path
    whole = pb.cursor().force(path)
    c = pb.cursor()
    halves = np.vstack([c.force(path[:15]), c.force(path[15:])])
    assert np.array_equal(whole, halves)
    assert np.allclose(c.probe, path[-1])
    one = pb.cursor().force(path[0])
    assert one.shape == (3,) and np.array_equal(one, whole[0])


def test_stiffness_is_the_force_slope(state):
    """Hermite stiffness against central differences of the force inside a cell."""
    pb = hapstate.Playback(state.dir)
    p = state.eval.path[len(state.eval.path) // 2]
    c = pb.cursor("hermite")
    c.force(state.eval.path[: len(state.eval.path) // 2 + 1])
    k = c.stiffness(p)
    assert k.shape == (3, 3)
    h = 1e-5 * float(pb.grid_spacing.min())
    fd = np.zeros((3, 3))
    for a in range(3):
        d = np.zeros(3)
        d[a] = h
        fd[:, a] = (c.force(p + d) - c.force(p - d)) / (2 * h)
        c.force(p)
    scale = np.abs(k).max()
    assert np.abs(fd - k).max() <= 1e-4 * scale
    assert c.stiffness(state.eval.path[:4]).shape == (4, 3, 3)


def test_deform_at_a_checkpoint_is_the_stored_configuration(state):
    """Walked exactly onto a check-point, the cursor shows the configuration stored there; the
    file's displacements are the catalogue's vectors (float32) of the configuration with the
    same force."""
    pb = hapstate.Playback(state.dir)
    c = pb.cursor("trilinear")
    assert np.all(c.deform() == 0) and c.probe is None
    path = state.eval.path
    c.force(path[: int(np.argmax(np.linalg.norm(state.eval.exact, axis=1))) + 1])
    ijk = c.anchor_checkpoint
    c.force(pb.grid_origin + ijk * pb.grid_spacing)
    config = c.anchor_configuration
    assert config >= 0 and np.any(pb.force(config) != 0)
    shown = c.deform()
    assert shown.shape == (pb.num_view_nodes, 3)
    assert np.abs(shown - pb.displacements(config)).max() <= 1e-6 * np.abs(shown).max()
    rows = hapstate.Catalogue(state.dir).configurations()
    same = np.flatnonzero(np.all(rows["force"] == pb.force(config), axis=1))
    assert len(same) == 1
    u = hapstate.Catalogue(state.dir).vectors(int(rows["id"][same[0]]))["u"][pb.view_nodes]
    assert np.abs(u - pb.displacements(config)).max() <= 1e-6 * np.abs(u).max()


def test_file_arrays(state):
    pb = hapstate.Playback(state.dir)
    assert pb.is_contact == (state.kind == "contact")
    n = pb.num_view_nodes
    assert pb.rest_positions.shape == (n, 3) and pb.view_nodes.shape == (n,)
    assert pb.triangles.shape[1] == 3 and pb.triangles.min() >= 0 and pb.triangles.max() < n
    g = pb.grid_points()
    assert g.shape == tuple(pb.grid_dims) + (3,)
    assert np.allclose(g[0, 0, 0], pb.grid_origin + pb.grid_lo * pb.grid_spacing)
    assert np.allclose(g[1, 0, 0] - g[0, 0, 0], [pb.grid_spacing[0], 0, 0])
    pb.verify()


def test_hundred_thousand_queries_in_one_call_under_a_second(grab_state):
    """The issue's bound (measured in docs/python.md on this machine class: ~0.05 s)."""
    pb = hapstate.Playback(grab_state.dir)
    rng = np.random.default_rng(1)
    lo = pb.grid_origin + pb.grid_lo * pb.grid_spacing
    span = (pb.grid_dims - 1) * pb.grid_spacing
    # A smooth wandering path inside the grid, as a hand would move.
    t = np.linspace(0, 40 * np.pi, 100_000)[:, None]
    phase = rng.uniform(0, 2 * np.pi, 3)
    path = lo + span * (0.5 + 0.45 * np.sin(t * np.array([1.0, 0.7, 0.3]) + phase))
    c = pb.cursor()
    c.force(path[:10])
    start = time.perf_counter()
    f = c.force(path)
    elapsed = time.perf_counter() - start
    assert f.shape == (100_000, 3) and np.all(np.isfinite(f))
    assert elapsed < 1.0


def test_errors_are_the_tools_messages(grab_state, tmp_path):
    with pytest.raises(hapstate.InputError, match="cannot open"):
        hapstate.Playback(tmp_path / "missing.bin")
    bad = tmp_path / "bad.bin"
    bad.write_bytes(b"not a playback file" * 10)
    with pytest.raises(hapstate.InputError, match=str(bad)):
        hapstate.Playback(bad)
    pb = hapstate.Playback(grab_state.dir)
    c = pb.cursor()
    with pytest.raises(ValueError, match=r"shape \(3, 2\)"):
        c.force(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="row 1 is not finite"):
        c.force(np.array([[4.0, 0.5, 1.0], [np.nan, 0, 0]]))
    with pytest.raises(ValueError, match="scheme 'cubic'"):
        pb.cursor("cubic")
    with pytest.raises(hapstate.InputError, match="out of range"):
        pb.force(pb.num_configurations)
    assert issubclass(hapstate.InputError, ValueError)
    assert issubclass(hapstate.EnvironmentError, OSError)
