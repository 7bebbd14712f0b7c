#!/usr/bin/env python3
"""Benchmark the precise solver on the bundled meshes, side by side with CalculiX.

For each mesh: a scene (the default liver scene with the mesh swapped, or a bunny scene), a
straight 10-point probe path (10 % of the mesh's bounding-box diagonal), then, alternating,
`hapstate-solve` and `ccx` on the same problem (`--export-ccx`), `--repeat` times each. Prints a
markdown table: DOFs, symbolic analysis, per-Newton-iteration assembly / factorisation / solve,
whole-path wall time of both solvers (medians) and their ratio. Both run single-threaded
(OMP_NUM_THREADS = OPENBLAS_NUM_THREADS = 1, hapstate-solve --threads 1) so the comparison is
like for like.

Usage: tools/bench_solve.py [--build build] [--repeat 3] [--meshes liver.msh,liverFine.vtu]
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIVER_SCENE = os.path.join(ROOT, "pipelines", "liver", "scene.toml")
BUNNY_SCENE = """[mesh]
file = "{mesh}"
unit = 0.01
[material]
law = "neohooke"
young = 5000.0
poisson = 0.45
[[fixed]]
box = [[-3.0, -1.0, -3.0], [3.0, -0.15, 3.0]]
[probe]
mode = "grab"
point = [-0.6, 2.7, -0.2]
max_force = 3.0
[grid]
spacing = 0.1
[solver]
substeps = 4
tolerance = 1e-8
max_iterations = 30
"""
BOXES = {  # bounding boxes from data/meshes/README.md (diagonal sets the path length)
    "liver.msh": ((-4.679, 0.218, -1.693), (1.803, 5.157, 2.729)),
    "liverCoarse.vtu": ((-4.65, 0.29, -1.67), (1.73, 5.16, 2.73)),
    "liverSemiFine.vtu": ((-4.65, 0.29, -1.67), (1.73, 5.16, 2.73)),
    "liverFine.vtu": ((-4.653, 0.289, -1.673), (1.726, 5.164, 2.729)),
    "bunny.msh": ((-1.891, -0.338, -1.236), (1.219, 2.742, 1.180)),
}


def scene_text(mesh_path, name):
    if name.startswith("liver"):
        text = open(LIVER_SCENE).read()
        return re.sub(r'file = "[^"]*"', 'file = "%s"' % mesh_path, text, count=1)
    return BUNNY_SCENE.format(mesh=mesh_path)


def run(cmd, cwd=None, env=None):
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit("bench_solve: %s failed (%d):\n%s%s" % (cmd[0], proc.returncode, proc.stdout, proc.stderr))
    return wall, proc.stdout + proc.stderr


def parse_timings(text):
    t = {}
    m = re.search(r"symbolic analysis ([\d.]+) ms; assembly ([\d.]+) ms x (\d+); "
                  r"factorisation ([\d.]+) ms x (\d+) \((\d+) PSD fallbacks\); solve ([\d.]+) ms total", text)
    t["analyze"], t["assembly"], t["factor"] = float(m[1]), float(m[2]), float(m[4])
    t["solve"] = float(m[7]) / max(1, int(m[5]))
    m = re.search(r"(\d+) DOFs, factor (\w+) \((\w+) ordering\), nnz\(L\) ([\d.e+]+)", text)
    t["dofs"], t["method"], t["ordering"], t["nnz"] = int(m[1]), m[2], m[3], float(m[4])
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--meshes", default=",".join(BOXES))
    ap.add_argument("--algorithm", default="fast", choices=["fast", "reference"],
                    help="hapstate-solve's algorithm (reference: the paper's fixed sub-steps)")
    args = ap.parse_args()
    solve = os.path.join(args.build, "tools", "hapstate-solve")
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    print("| mesh | DOFs | factor | symbolic ms | assembly ms/it | factorisation ms/it | solve ms/it "
          "| hapstate path s | ccx path s | ccx / hapstate |")
    print("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name in args.meshes.split(","):
        lo, hi = BOXES[name]
        diag = [h - l for l, h in zip(lo, hi)]
        length = 0.1 * sum(d * d for d in diag) ** 0.5
        with tempfile.TemporaryDirectory() as tmp:
            scene = os.path.join(tmp, "scene.toml")
            with open(scene, "w") as f:
                f.write(scene_text(os.path.join(ROOT, "data", "meshes", name), name))
            ccx_dir = os.path.join(tmp, "ccx")
            # Straight path: 10 points towards the direction (-1, 1, 0.5) from rest.
            d = [-1.0, 1.0, 0.5]
            n = sum(x * x for x in d) ** 0.5
            cmd = [solve, scene, "--by"] + ["%.9g" % (length * x / n) for x in d] + [
                "--steps", "10", "-o", os.path.join(tmp, "ours.csv"), "--timings", "-q",
                "--algorithm", args.algorithm, "--threads", "1"]
            run(cmd + ["--export-ccx", ccx_dir], env=env)
            ours, ccx, timings = [], [], None
            for _ in range(args.repeat):
                wall, text = run(cmd, env=env)
                ours.append(wall)
                timings = parse_timings(text)
                wall, _ = run(["ccx", "-i", "problem"], cwd=ccx_dir, env=env)
                ccx.append(wall)
            mo, mc = statistics.median(ours), statistics.median(ccx)
            t = timings
            print("| %s | %d | %s/%s, nnz(L) %.3g | %.1f | %.2f | %.2f | %.2f | %.3f | %.3f | %.1f |" % (
                name, t["dofs"], t["method"], t["ordering"], t["nnz"], t["analyze"], t["assembly"],
                t["factor"], t["solve"], mo, mc, mc / mo))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
