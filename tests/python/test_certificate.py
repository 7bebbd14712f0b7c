"""hapstate-certify (run by `hapstate run` in the fixtures): the certificate against
hapstate-eval on the same seeds, its headline in the playback file, stale after a re-index,
resumable by paths (docs/certificate.md)."""

import json
import shutil
import subprocess

import numpy as np

import hapstate
from conftest import TOOLS, EvalPath

STAGES = TOOLS.parent / "stages"


def summary(state_dir):
    out = subprocess.run([TOOLS / "hapstate-inspect", "--state", state_dir, "summary", "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["certificate"]


def test_certificate_is_not_below_eval(state, tmp_path):
    """20 paths of 30 steps by default; hapstate-eval with --steps 30 on seeds 1..3 measures the
    same paths: the certificate's worst is at least each of them, and equals their worst step
    when that is the worst overall (both come from the same solver and cursors)."""
    c = summary(state.dir)
    assert c is not None and not c["stale"] and c["complete"]
    assert c["paths"] == 20 and c["steps_per_path"] == 30 and c["steps"] == 600
    for seed in (1, 2, 3):
        csv = tmp_path / f"eval-{seed}.csv"
        subprocess.run([TOOLS / "hapstate-eval", "--state", state.dir, "--steps", "30", "--seed",
                        str(seed), "--csv", csv, "--no-plot"], check=True, capture_output=True)
        e = EvalPath(csv)
        for scheme, forces in (("hermite", e.hermite), ("trilinear", e.trilinear)):
            errors = np.linalg.norm(forces - e.exact, axis=1) / e.largest
            assert c["force_error"][scheme]["worst"] >= errors.max() - 1e-9, (scheme, seed)
            newtons = np.linalg.norm(forces - e.exact, axis=1).max()
            assert c["force_error"][scheme]["worst_newtons"] >= newtons - 1e-12
    for scheme in ("hermite", "trilinear"):
        f = c["force_error"][scheme]
        assert 0 <= f["p99"] <= f["worst"]
    assert len([w for w in c["worst"] if w["scheme"] == "hermite"]) == 5
    worst = max((w for w in c["worst"] if w["scheme"] == "hermite"),
                key=lambda w: w["force_error"])
    assert worst["force_error"] == c["force_error"]["hermite"]["worst"]
    if state.kind == "contact":
        assert c["contact"]["steps"] > 0 and c["contact"]["onsets"] > 0
    assert c["stiffness"]["largest_n_per_mm"] > 0
    assert c["haptic_query_ns"]["queries"] == 600 * 10
    assert 0 < c["haptic_query_ns"]["median"] <= c["haptic_query_ns"]["p99_9"]


def test_playback_file_carries_the_headline(state):
    c = summary(state.dir)
    pb = hapstate.Playback(state.dir)
    h = pb.certificate
    assert h is not None and h["paths"] == c["paths"] and h["steps"] == c["steps"]
    for scheme in ("hermite", "trilinear"):
        assert h[scheme]["force_error_worst"] == c["force_error"][scheme]["worst"]
        assert h[scheme]["force_error_p99"] == c["force_error"][scheme]["p99"]
    assert h["stiffness_n_per_mm"] == c["stiffness"]["largest_n_per_mm"]
    pb.verify()


def test_stale_after_reindex_and_resumable(state, tmp_path):
    work = tmp_path / "state"
    shutil.copytree(state.dir, work)
    # Another playback file (surface nodes only: another source hash) makes it stale.
    subprocess.run([STAGES / "hapstate-index", "--state", work, "--nodes", "surface"],
                   check=True, capture_output=True)
    assert summary(work)["stale"]
    assert hapstate.Playback(work).certificate is None
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "3", "-q"],
                         check=True, capture_output=True, text=True).stdout
    assert "3 of 3 paths measured now (20 stale deleted)" in run
    c = summary(work)
    assert not c["stale"] and c["paths"] == 3
    # More paths later: only the new ones are measured.
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "5", "-q"],
                         check=True, capture_output=True, text=True).stdout
    assert "2 of 2 paths measured now (0 stale deleted)" in run
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "5", "-q"],
                         check=True, capture_output=True, text=True).stdout
    assert "unchanged" in run
    assert hapstate.Playback(work).certificate["paths"] == 5
    # Fewer paths: the seeds above are dropped, nothing is solved.
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "3", "-q"],
                         check=True, capture_output=True, text=True).stdout
    assert "0 of 0 paths measured now (2 stale deleted)" in run
    assert summary(work)["paths"] == 3 and hapstate.Playback(work).certificate["paths"] == 3


def test_two_sided_solves_at_the_worst_steps(state, tmp_path):
    """--check-above 0: the worst step of each cursor gets the two-sided solves (three axes, half
    a spacing each way), stored with the certificate and shown by summary; a certificate without
    them (measured with the default threshold, or before they existed) is measured again only for
    them. The beam has one
    equilibrium there: both approaches' forces equal the path's precise force at that step (the
    same solver, another route: 1e-5 of the force covers the residual tolerance and the contact's
    gap tolerance, 1e-6 of the radius, which left 2.4e-6 of the force). Resumable: a
    second run finds them stored."""
    work = tmp_path / "state"
    shutil.copytree(state.dir, work)
    subprocess.run([STAGES / "hapstate-index", "--state", work, "--nodes", "surface"],
                   check=True, capture_output=True)
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "3",
                          "--check-above", "inf", "-q"], check=True, capture_output=True,
                         text=True)
    assert "3 of 3 paths measured now (20 stale deleted), 0 worst steps" in run.stdout
    assert summary(work)["equilibria"] == []
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "3",
                          "--check-above", "0"], check=True, capture_output=True, text=True)
    assert "0 of 0 paths measured now (0 stale deleted)" in run.stdout
    assert "given two-sided solves" in run.stdout and "0 worst steps" not in run.stdout
    assert "two-sided solves at seed" in run.stdout, run.stdout
    c = summary(work)
    rows = c["equilibria"]
    worst = {(w["seed"], w["step"]) for w in c["worst"]
             if w["force_error"] == c["force_error"][w["scheme"]]["worst"]}
    assert {(r["seed"], r["step"]) for r in rows} == worst
    assert len(rows) == 3 * len(worst)
    cat = hapstate.Catalogue(work)
    spacing = np.asarray(hapstate.Playback(work).grid_spacing)
    for r in rows:
        assert r["verdict"] == "one", r
        assert r["along"] == 0.5 * spacing["xyz".index(r["axis"])]
        exact = cat.query(f"SELECT force FROM certificate_step WHERE seed = {r['seed']} "
                          f"AND step = {r['step']}")["force"][0]
        for side in ("force_minus", "force_plus"):
            assert abs(np.linalg.norm(r[side]) - exact) <= 1e-5 * exact + 1e-12, (r, exact)
    run = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--paths", "3",
                          "--check-above", "0", "-q"], check=True, capture_output=True, text=True)
    assert "unchanged" in run.stdout
    r = subprocess.run([STAGES / "hapstate-certify", "--state", work, "--check-above", "-1"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "--check-above" in r.stderr


def test_bad_options_and_state(tmp_path):
    r = subprocess.run([STAGES / "hapstate-certify", "--state", tmp_path / "nowhere"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "nowhere" in r.stderr
    r = subprocess.run([STAGES / "hapstate-certify", "--state", tmp_path, "--paths", "0"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "--paths" in r.stderr
