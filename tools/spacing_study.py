#!/usr/bin/env python3
"""Playback accuracy against grid spacing on the bundled liver scene (docs/benchmarks.md).

For each spacing, a copy of pipelines/liver/scene.toml with that spacing and a fixed workspace
(the probe's rest position +- HALF_WIDTH cm) is precomputed with `hapstate run` (import -> grid
-> expand -> compact -> index, all nodes) and evaluated with `hapstate-eval` on the same seeded
20-step random paths (step 0.25 cm). Prints a Markdown table: precompute time beside the max
force and deformation errors of both schemes (worst over the seeds).

  python3 tools/spacing_study.py --build build --out out/study --spacings 0.75 0.5 0.375
"""
import argparse
import csv
import pathlib
import re
import subprocess
import sys
import time

REST = (-2.51058, 3.4868, 2.21873)  # node 100 of data/meshes/liver.msh: the grabbed node


def scene_variant(source, spacing, half_width, mesh):
    text = source.read_text()
    text = re.sub(r'file = "[^"]*"', f'file = "{mesh}"', text, count=1)
    lo = [c - half_width for c in REST]
    hi = [c + half_width for c in REST]
    grid = f"[grid]\nspacing = {spacing!r}\nbox = [[{lo[0]!r}, {lo[1]!r}, {lo[2]!r}], [{hi[0]!r}, {hi[1]!r}, {hi[2]!r}]]\n"
    return re.sub(r"\[grid\]\n(?:[^\[\n][^\n]*\n|\n)*", grid + "\n", text, count=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default="out/study")
    ap.add_argument("--spacings", type=float, nargs="+", default=[0.75, 0.5, 0.375])
    ap.add_argument("--half-width", type=float, default=1.51)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    build = pathlib.Path(args.build).resolve()
    source = root / "pipelines/liver/scene.toml"
    mesh = (root / "data/meshes/liver.msh").resolve()
    rows = []
    for h in args.spacings:
        d = pathlib.Path(args.out) / f"h{h:.4f}"
        d.mkdir(parents=True, exist_ok=True)
        scene = d / "scene.toml"
        scene.write_text(scene_variant(source, h, args.half_width, mesh))
        t0 = time.monotonic()
        run = subprocess.run([build / "tools/hapstate", "run", scene, "--state", d / "state", "--threads",
                              str(args.threads), "--nodes", "all", "-q"], capture_output=True, text=True)
        seconds = time.monotonic() - t0
        if run.returncode != 0:
            sys.exit(f"hapstate run failed for h = {h}:\n{run.stdout}\n{run.stderr}")
        expand = re.search(r"expand:\s+(.*)", run.stdout).group(1)
        worst = {"trilinear_force_error": 0, "hermite_force_error": 0,
                 "trilinear_deformation_error_all": 0, "trilinear_deformation_error_surface": 0}
        fmax = 0
        for seed in args.seeds:
            csv_file = d / f"eval-{seed}.csv"
            ev = subprocess.run([build / "tools/hapstate-eval", "--state", d / "state", "--steps", "20",
                                 "--seed", str(seed), "--step-length", "0.25", "--csv", csv_file, "--plot",
                                 d / f"eval-{seed}.png"], capture_output=True, text=True)
            if ev.returncode != 0:
                sys.exit(f"hapstate-eval failed for h = {h}, seed {seed}:\n{ev.stdout}\n{ev.stderr}")
            for r in csv.DictReader(open(csv_file)):
                for k in worst:
                    worst[k] = max(worst[k], float(r[k]))
                fmax = max(fmax, (float(r["fx_exact"]) ** 2 + float(r["fy_exact"]) ** 2 + float(r["fz_exact"]) ** 2) ** 0.5)
        rows.append((h, seconds, expand, worst, fmax))
        print(f"h = {h:.4f}: {seconds:.0f} s; {expand}", file=sys.stderr)
    print("| spacing (cm) | precompute (s) | max force error trilinear | max force error Hermite | "
          "max deformation error (all nodes) | (surface) | max |f*| (N) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for h, seconds, expand, w, fmax in rows:
        print(f"| {h:.4f} | {seconds:.0f} | {100 * w['trilinear_force_error']:.2f} % | "
              f"{100 * w['hermite_force_error']:.2f} % | {100 * w['trilinear_deformation_error_all']:.2f} % | "
              f"{100 * w['trilinear_deformation_error_surface']:.2f} % | {fmax:.3f} |")


if __name__ == "__main__":
    main()
