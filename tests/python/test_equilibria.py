"""hapstate.equilibria: a position reached from either side by the precise solver. On the bunny's
sharp vertex under a 1.5 mm sphere (bench/scenes/bunny-apex.toml) the apex slips off to one side
or the other: measured 2026-11-29 along x through the certificate's worst step, the force's x
component is -2.0 mN reached from -x and +7.3 mN from +x (docs/contact.md, "Measured"). Under a
sphere of twice the radius pressed as deep the same line has one equilibrium (the two agree to
0.0005 mN). The verdict's rules (order, tolerance, floor) are tested in tests/eval/equilibria_test.cc."""

import os
import re
import subprocess
import sys

import hapstate
import hapstate.equilibria as eq
from conftest import BUILD, SOURCE

APEX = SOURCE / "bench/scenes/bunny-apex.toml"
WORST = [-0.04855, 0.4907, 1.194]  # the certificate's worst step (seed 16, step 11)
ALONG = [0.002, 0.0, 0.0]


def test_sharp_vertex_has_two_equilibria():
    r = eq.from_both_sides(APEX, WORST, ALONG, steps=4)
    assert r["converged_minus"] and r["converged_plus"]
    # The two branches (docs/contact.md): x -2.0 and +7.3 mN, |f| about 23 mN. Tolerances: the
    # solver's (1e-8 relative) is far below; 0.3 mN allows another descent's round-off.
    assert abs(1e3 * r["force_minus"][0] - (-2.00)) < 0.3
    assert abs(1e3 * r["force_plus"][0] - 7.33) < 0.3
    assert r["difference"] > 0.3 * r["largest"]
    assert r["verdict"] == eq.TWO


def test_larger_sphere_has_one(tmp_path):
    # The same vertex under r = 0.06, the rest point and the position moved out along the
    # vertex's normal so that the sphere is pressed as deep (0.0163 unit past the apex).
    text = APEX.read_text()
    for pattern, replacement in (
            (r'"\.\./\.\./data/meshes/bunny\.msh"', f'"{SOURCE / "data/meshes/bunny.msh"}"'),
            (r"^radius = 0\.03$", "radius = 0.06"),
            (r"^point = .*$", "point = [-0.045349, 0.483142, 1.243642]"),
            (r"^box = \[\[-0\.057856.*$",
             "box = [[-0.055349, 0.473142, 1.223642], [-0.035349, 0.493142, 1.243642]]")):
        text, n = re.subn(pattern, replacement, text, flags=re.M)
        assert n == 1, pattern  # the scene file changed: this test must follow it
    scene = tmp_path / "apex-r006.toml"
    scene.write_text(text)
    r = eq.from_both_sides(scene, [-0.046030, 0.487550, 1.223728], ALONG, steps=4)
    assert r["converged_minus"] and r["converged_plus"]
    assert r["largest"] > 0.015  # pressed: about 23 mN
    assert r["difference"] < 1e-3 * r["largest"]
    assert r["verdict"] == eq.ONE


def test_command_line_and_bad_input(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(BUILD / "python")}
    # Without --along: half the grid spacing (0.005) along x, y and z in turn.
    run = subprocess.run([sys.executable, "-m", "hapstate.equilibria", str(APEX), *map(str, WORST),
                          "--steps", "4"], capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    assert "along (0.005, 0, 0):" in run.stdout and "along (0, 0, 0.005):" in run.stdout
    assert "two equilibria" in run.stdout and "the force jumps near here" in run.stdout
    # Bad input: the scene parser's messages, naming the file and the place; exit 2.
    bad = tmp_path / "no-probe.toml"
    bad.write_text('[mesh]\nfile = "x.msh"\n[probe]\nmode = "contact"\n')
    for extra in ([], ["--along", "1", "0", "0"]):
        run = subprocess.run([sys.executable, "-m", "hapstate.equilibria", str(bad), "0", "0", "0",
                              *extra], capture_output=True, text=True, env=env)
        assert run.returncode == 2
        assert "no-probe.toml:3: missing key 'probe.point'" in run.stderr, run.stderr
        assert "no-probe.toml: missing table [grid]" in run.stderr
    run = subprocess.run([sys.executable, "-m", "hapstate.equilibria", str(APEX), *map(str, WORST),
                          "--tolerance", "0"], capture_output=True, text=True, env=env)
    assert run.returncode == 2 and "tolerance" in run.stderr
    try:
        eq.from_both_sides(APEX, WORST, [0.0, 0.0, 0.0])
    except hapstate.InputError as e:
        assert "along" in str(e)
    else:
        raise AssertionError("a zero approach was accepted")
