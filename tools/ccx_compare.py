#!/usr/bin/env python3
"""Compare hapstate path-solver results with CalculiX on the same problem.

The ccx directory is one written by hapstate::write_ccx_deck (problem.inp, path.csv,
hapstate.json). This tool runs `ccx -i problem` there (unless problem.dat is already newer
than problem.inp), reads problem.dat and compares, per path point:

  force:        ours (fx,fy,fz: force felt by the user, N) against -(sum of ccx RF over the
                probe DOFs); error = |f_ours - f_ccx| / max over the path of |f_ccx|
  displacement: ours (--ours-displacements, mesh units) against ccx U / unit;
                error = max over nodes of |u_ours - u_ccx|_inf / max over path and nodes of |u_ccx|

Exit status: 0 all within --rtol, 1 some error above --rtol (or a ccx failure), 2 bad input.
Formats and sign conventions: docs/calculix.md. Standard library only.
"""

import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

JOB = "problem"
EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2


class InputError(Exception):
    pass


def fortran_float(token):
    """Parse a ccx number; Fortran drops the E of 3-digit exponents ('1.0-100')."""
    try:
        return float(token)
    except ValueError:
        m = re.fullmatch(r"([-+]?[0-9.]+)([-+][0-9]+)", token)
        if not m:
            raise
        return float(m.group(1) + "E" + m.group(2))


HEADER = re.compile(r"^\s*(displacements|forces|total force) \(.*\) for set (\S+) and time\s+(\S+)")


def read_dat(path):
    """Tables of a ccx .dat: list of dicts quantity, set, time, rows [(id or None, x, y, z)]."""
    blocks, current = [], None
    with open(path) as f:
        for line_no, line in enumerate(f, 1):
            text = line.strip()
            if not text:
                if current is not None and current["rows"]:
                    current = None
                continue
            m = HEADER.match(line)
            if m:
                current = {"quantity": m.group(1), "set": m.group(2),
                           "time": fortran_float(m.group(3)), "rows": []}
                blocks.append(current)
                continue
            if " for set " in line and " and time " in line:
                current = None  # a table we do not read (stresses, ...)
                continue
            if current is None:
                continue
            tokens = text.split()
            try:
                if current["quantity"] == "total force":
                    if len(tokens) != 3:
                        raise ValueError
                    current["rows"].append((None,) + tuple(fortran_float(t) for t in tokens))
                else:
                    if len(tokens) != 4:
                        raise ValueError
                    current["rows"].append((int(tokens[0]),) +
                                           tuple(fortran_float(t) for t in tokens[1:]))
            except ValueError:
                raise InputError(f"{path}:{line_no}: malformed row '{text}'")
    return blocks


def ccx_results(ccx_dir, meta):
    """Per path point (0-based): dict u (list of [ux,uy,uz], mesh units), felt ([fx,fy,fz], N)."""
    unit, n, points = meta["unit"], meta["num_nodes"], meta["num_points"]
    probe_dofs = {(node, c) for node, c in meta["probe_dofs"]}
    u_at, rf_at = {}, {}
    shift = meta.get("first_point_time", 1) - 1  # a rest step (gravity) comes first
    for b in read_dat(os.path.join(ccx_dir, JOB + ".dat")):
        k = round(b["time"]) - shift
        if abs(b["time"] - shift - k) > 1e-6 or not 1 <= k <= points:
            continue
        if b["quantity"] == "displacements" and b["set"] == "NALL":
            u_at[k] = b
        elif b["quantity"] == "forces" and b["set"] == "PROBE":
            rf_at[k] = b
    out = []
    for k in range(1, points + 1):
        if k not in u_at or (probe_dofs and k not in rf_at):
            raise InputError(f"{ccx_dir}: ccx printed no results for path point {k} "
                             f"(see {os.path.join(ccx_dir, 'ccx.log')})")
        u = [[0.0, 0.0, 0.0] for _ in range(n)]
        for node_id, x, y, z in u_at[k]["rows"]:
            u[node_id - 1] = [x / unit, y / unit, z / unit]
        on_probe = [0.0, 0.0, 0.0]
        for node_id, *f in rf_at.get(k, {"rows": []})["rows"]:
            for c in range(3):
                if (node_id - 1, c) in probe_dofs:
                    on_probe[c] += f[c]
        # ccx's RF is the internal force alone: the felt force adds the grabbed nodes' own
        # weight (zero at the rest state; absent without gravity).
        weight = meta.get("probe_body_force", [0.0, 0.0, 0.0])
        out.append({"u": u, "felt": [w - f for f, w in zip(on_probe, weight)]})
    return out


def run_ccx_if_needed(ccx_dir, ccx_exe, force):
    inp = os.path.join(ccx_dir, JOB + ".inp")
    dat = os.path.join(ccx_dir, JOB + ".dat")
    if not os.path.exists(inp):
        raise InputError(f"{inp}: no CalculiX deck (write it with hapstate::write_ccx_deck)")
    if not force and os.path.exists(dat) and os.path.getmtime(dat) >= os.path.getmtime(inp):
        return
    log_path = os.path.join(ccx_dir, "ccx.log")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    try:
        with open(log_path, "w") as log:
            rc = subprocess.call([ccx_exe, "-i", JOB], cwd=ccx_dir, stdout=log,
                                 stderr=subprocess.STDOUT, env=env)
    except FileNotFoundError:
        raise InputError(f"cannot run '{ccx_exe}': is calculix-ccx installed?")
    with open(log_path) as log:
        error = any("*ERROR" in line for line in log)
    if rc != 0 or error:
        raise RuntimeError(f"ccx failed in {ccx_dir} (status {rc}); see {log_path}")


def read_csv_rows(path, required):
    with open(path, newline="") as f:
        reader = csv.DictReader(row for row in f if row.strip() and not row.startswith("#"))
        missing = [c for c in required if c not in (reader.fieldnames or [])]
        if missing:
            raise InputError(f"{path}: missing column(s) {', '.join(missing)}")
        rows = []
        for line_no, row in enumerate(reader, 2):
            try:
                rows.append({c: float(row[c]) for c in required})
            except (TypeError, ValueError):
                raise InputError(f"{path}:{line_no}: malformed row")
        return rows


def match_points(path, ours, tol):
    """Index into `ours` for each path point: the next row (in file order) at that position."""
    matched, i = [], 0
    for k, p in enumerate(path):
        while i < len(ours) and max(abs(ours[i][c] - p[j]) for j, c in enumerate("xyz")) > tol:
            i += 1
        if i == len(ours):
            raise InputError(f"our results have no row at path point {k + 1} "
                             f"({p[0]:g}, {p[1]:g}, {p[2]:g}) after the previous match")
        matched.append(i)
        i += 1
    return matched


def read_displacements(path, wanted_steps):
    """{step: {node: [ux, uy, uz]}} for the steps in wanted_steps (mesh units)."""
    out = {s: {} for s in wanted_steps}
    for row in read_csv_rows(path, ["step", "node", "ux", "uy", "uz"]):
        step = int(row["step"])
        if step in out:
            out[step][int(row["node"])] = [row["ux"], row["uy"], row["uz"]]
    return out


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ccx-dir", required=True, help="directory written by write_ccx_deck")
    ap.add_argument("--ours", required=True,
                    help="path-solver CSV: step,x,y,z,fx,fy,fz,... (mesh units, N)")
    ap.add_argument("--ours-displacements",
                    help="CSV step,node,ux,uy,uz (mesh units, 0-based nodes)")
    ap.add_argument("--rtol", type=float, default=1e-4, help="relative tolerance (default 1e-4)")
    ap.add_argument("--ccx", default=os.environ.get("HAPSTATE_CCX", "ccx"),
                    help="ccx executable (default $HAPSTATE_CCX or ccx)")
    ap.add_argument("--rerun", action="store_true", help="run ccx even if problem.dat is current")
    args = ap.parse_args(argv)

    try:
        with open(os.path.join(args.ccx_dir, "hapstate.json")) as f:
            meta = json.load(f)
        path = [(r["x"], r["y"], r["z"])
                for r in read_csv_rows(os.path.join(args.ccx_dir, "path.csv"), ["x", "y", "z"])]
        if len(path) != meta["num_points"]:
            raise InputError(f"{args.ccx_dir}: path.csv and hapstate.json disagree")
        ours = read_csv_rows(args.ours, ["step", "x", "y", "z", "fx", "fy", "fz"])
        scale = max([1.0] + [abs(c) for p in path for c in p])
        matched = match_points(path, ours, 1e-9 * scale)
        disp = None
        if args.ours_displacements:
            disp = read_displacements(args.ours_displacements,
                                      {int(ours[i]["step"]) for i in matched})
        run_ccx_if_needed(args.ccx_dir, args.ccx, args.rerun)
        ccx = ccx_results(args.ccx_dir, meta)
    except (InputError, OSError, json.JSONDecodeError, KeyError) as e:
        print(f"ccx_compare: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except RuntimeError as e:
        print(f"ccx_compare: {e}", file=sys.stderr)
        return EXIT_FAILED

    f_scale = max([norm(r["felt"]) for r in ccx] + [1e-300])
    u_scale = max([abs(c) for r in ccx for u in r["u"] for c in u] + [1e-300])
    worst_f = worst_u = 0.0
    print(f"CalculiX cross-check of {args.ours} against {args.ccx_dir} "
          f"(law {meta['law']}, {meta['num_nodes']} nodes, {len(path)} points)")
    print(f"force scale max|f_ccx| = {f_scale:.6e} N, displacement scale max|u_ccx| = "
          f"{u_scale:.6e} mesh units; rtol {args.rtol:g}")
    print(f"{'pt':>4} {'step':>5} {'fx_ccx':>13} {'fy_ccx':>13} {'fz_ccx':>13} "
          f"{'fx_ours':>13} {'fy_ours':>13} {'fz_ours':>13} {'err_f':>9} {'err_u':>9}")
    for k, (i, c) in enumerate(zip(matched, ccx)):
        row = ours[i]
        f_ours = [row["fx"], row["fy"], row["fz"]]
        err_f = norm([a - b for a, b in zip(f_ours, c["felt"])]) / f_scale
        err_u_text = "-"
        if disp is not None:
            ours_u = disp[int(row["step"])]
            if not ours_u:
                print(f"ccx_compare: no displacements for step {int(row['step'])} in "
                      f"{args.ours_displacements}", file=sys.stderr)
                return EXIT_BAD_INPUT
            err_u = 0.0
            for node, u in ours_u.items():
                if not 0 <= node < meta["num_nodes"]:
                    print(f"ccx_compare: node {node} out of range", file=sys.stderr)
                    return EXIT_BAD_INPUT
                err_u = max(err_u, max(abs(a - b) for a, b in zip(u, c["u"][node])))
            err_u /= u_scale
            worst_u = max(worst_u, err_u)
            err_u_text = f"{err_u:9.2e}"
        worst_f = max(worst_f, err_f)
        print(f"{k + 1:>4} {int(row['step']):>5} " +
              " ".join(f"{v:>13.6e}" for v in c["felt"] + f_ours) +
              f" {err_f:9.2e} {err_u_text:>9}")
    ok = worst_f <= args.rtol and worst_u <= args.rtol
    print(f"max relative error: force {worst_f:.2e}" +
          (f", displacement {worst_u:.2e}" if disp is not None else "") +
          (" -- OK" if ok else f" -- ABOVE rtol {args.rtol:g}"))
    return EXIT_OK if ok else EXIT_FAILED


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
