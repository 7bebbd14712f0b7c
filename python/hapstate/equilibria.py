"""Two equilibria at one probe position: the precise solver reaching it from either side.

Where a contact probe is pressed on a sharp vertex or the tip of a thin flap, the surface can
slide off the sphere to one side or the other, and the force jumps where one of two equilibria
ends (docs/contact.md, "Measured"; docs/certificate.md, "When it is not good enough"). No
interpolation follows a jump, so no grid spacing or refinement depth brings such an error down.
This checks a position for it: the probe goes from rest to `point - along` and slides from there
to `point`, and again by way of `point + along`; two different forces at the same position are
two equilibria. Newton failing on one side only is likely an equilibrium that ends between the
two sides (where it ends, Newton has no nearby state to converge to).

    import hapstate.equilibria as eq
    r = eq.from_both_sides("scene.toml", [x, y, z], along=[0.002, 0, 0])
    r["difference"]   # |f(-) - f(+)| in N

From the shell (positions in mesh units, as `hapstate-inspect summary` prints them):

    PYTHONPATH=build/python /usr/bin/python3 -m hapstate.equilibria SCENE X Y Z [--along DX DY DZ]

(without --along: half the grid spacing along x, then y, then z). A short approach can miss a
range where both equilibria exist: both approaches then start on the same side of it.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from typing import Any

import numpy as np

from ._core import InputError, solve


def _read_scene(scene: Any) -> dict[str, Any]:
    try:
        with open(scene, "rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{scene}: {e}") from None


def _rest_point(scene: Any) -> np.ndarray:
    point = _read_scene(scene).get("probe", {}).get("point")
    if point is None or len(point) != 3:
        raise InputError(f"{scene}: [probe] point: expected 3 numbers (the probe's rest position)")
    return np.asarray(point, dtype=float)


def from_both_sides(scene: str, point: Any, along: Any, steps: int = 10) -> dict[str, Any]:
    """The precise force at `point` reached by way of `point - along` and of `point + along`.

    Each approach starts at rest, moves the probe to its start in `steps` equal moves and slides
    it to `point` in `steps` more. Returns a dict: force_minus and force_plus (N, the force felt
    at `point` by each), started_minus and started_plus (whether that approach's start was
    reached: every solve from rest converged), converged_minus and converged_plus (whether every
    solve of that approach converged, at `point` too), difference (|force_minus - force_plus|, N) and
    largest (the larger |force|, N).
    """
    p = np.asarray(point, dtype=float).reshape(3)
    d = np.asarray(along, dtype=float).reshape(3)
    if not np.all(np.isfinite(p)) or not np.all(np.isfinite(d)) or not np.any(d):
        raise InputError("from_both_sides: point and along must be finite, along not zero")
    if steps < 1:
        raise InputError(f"from_both_sides: steps must be >= 1 (got {steps})")
    rest = _rest_point(scene)
    result: dict[str, Any] = {}
    for side, start in (("minus", p - d), ("plus", p + d)):
        path = [rest + (start - rest) * (k / steps) for k in range(1, steps + 1)]
        path += [start + (p - start) * (k / steps) for k in range(1, steps + 1)]
        r = solve(scene, np.array(path))
        result["force_" + side] = np.asarray(r["force"][-1], dtype=float)
        result["started_" + side] = bool(np.all(r["converged"][:steps]))
        result["converged_" + side] = bool(np.all(r["converged"]))
    result["difference"] = float(np.linalg.norm(result["force_minus"] - result["force_plus"]))
    result["largest"] = float(max(np.linalg.norm(result["force_minus"]),
                                  np.linalg.norm(result["force_plus"])))
    return result


def _half_spacing(scene: str) -> np.ndarray:
    """Half the scene's grid spacing per axis: [grid] spacing, or box and dims."""
    grid = _read_scene(scene).get("grid", {})
    if "spacing" in grid:
        h = np.broadcast_to(np.asarray(grid["spacing"], dtype=float), (3,))
    elif "dims" in grid and "box" in grid:
        box = np.asarray(grid["box"], dtype=float)
        h = (box[1] - box[0]) / (np.broadcast_to(np.asarray(grid["dims"], dtype=float), (3,)) - 1)
    else:
        raise InputError(f"{scene}: [grid]: no spacing (nor box and dims): give --along")
    return 0.5 * h


def _verdict(r: dict[str, Any], tolerance: float) -> tuple[int, str]:
    """0 and what was found, or 3 and why nothing was decided."""
    if not (r["started_minus"] and r["started_plus"]):
        return 3, ("not decided: an approach did not reach its start from rest (try a shorter "
                   "--along or more --steps)")
    if r["converged_minus"] != r["converged_plus"]:
        failed = "-along" if not r["converged_minus"] else "+along"
        return 0, (f"likely an equilibrium ending near here: Newton failed on the approach from "
                   f"{failed} only, as it does where the state it follows ends")
    if not r["converged_minus"]:
        return 3, "not decided: neither approach converged"
    share = r["difference"] / r["largest"] if r["largest"] > 0 else 0.0
    if share > tolerance:
        return 0, "two equilibria: the force jumps near here"
    return 0, "one equilibrium here (from these two sides)"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python3 -m hapstate.equilibria",
        description="Solve a probe position reached from either side (docs/certificate.md, "
        "\"When it is not good enough\"): two different forces are two equilibria, a jump "
        "no grid spacing or refinement depth removes.")
    ap.add_argument("scene", help="scene file (TOML)")
    ap.add_argument("point", type=float, nargs=3, metavar=("X", "Y", "Z"),
                    help="probe position, mesh units")
    ap.add_argument("--along", type=float, nargs=3, metavar=("DX", "DY", "DZ"),
                    help="the approach: from POINT - ALONG and from POINT + ALONG (mesh units; "
                    "default: half the grid spacing along x, then y, then z)")
    ap.add_argument("--steps", type=int, default=10,
                    help="moves from rest to each approach's start, and from there to POINT "
                    "(default 10)")
    ap.add_argument("--tolerance", type=float, default=0.01,
                    help="a difference above this fraction of the larger force counts as two "
                    "equilibria (default 0.01)")
    args = ap.parse_args(argv)
    try:
        if args.along is not None:
            approaches = [np.asarray(args.along, dtype=float)]
        else:
            half = _half_spacing(args.scene)
            approaches = [half[a] * np.eye(3)[a] for a in range(3)]
        results = [(d, from_both_sides(args.scene, args.point, d, args.steps))
                   for d in approaches]
    except (InputError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    found, undecided = False, False
    for d, r in results:
        mn, pl = 1e3 * r["force_minus"], 1e3 * r["force_plus"]
        share = r["difference"] / r["largest"] if r["largest"] > 0 else 0.0
        code, text = _verdict(r, args.tolerance)
        print(f"along ({d[0]:g}, {d[1]:g}, {d[2]:g}):")
        print(f"  from -along: ({mn[0]:.4f}, {mn[1]:.4f}, {mn[2]:.4f}) mN")
        print(f"  from +along: ({pl[0]:.4f}, {pl[1]:.4f}, {pl[2]:.4f}) mN")
        print(f"  difference {1e3 * r['difference']:.4f} mN ({100 * share:.2f} % of the larger "
              "force)")
        print(f"  {text}")
        found = found or (code == 0 and not text.startswith("one"))
        undecided = undecided or code != 0
    if found:
        print("the force jumps near here: no grid spacing or refinement depth removes that error "
              "(docs/certificate.md, \"When it is not good enough\")")
        return 0
    return 3 if undecided else 0


if __name__ == "__main__":
    sys.exit(main())
