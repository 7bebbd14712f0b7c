"""Two equilibria at one probe position: the precise solver reaching it from either side.

Where a contact probe is pressed on a sharp vertex or the tip of a thin flap, the surface can
slide off the sphere to one side or the other, and the force jumps where one of two equilibria
ends (docs/contact.md, "Measured"; docs/certificate.md, "When it is not good enough"). No
interpolation follows a jump, so no grid spacing or refinement depth brings such an error down.
This checks a position for it: the body is loaded from rest to `point - along` and then to
`point`, and again to `point + along` and then to `point`; two different forces at the same
position are two equilibria.

    import hapstate.equilibria as eq
    r = eq.from_both_sides("scene.toml", [x, y, z], along=[0.002, 0, 0])
    r["difference"]   # |f(-) - f(+)| in N

From the shell (positions in mesh units, as `hapstate-inspect summary` prints them):

    PYTHONPATH=build/python /usr/bin/python3 -m hapstate.equilibria SCENE X Y Z --along DX DY DZ
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from typing import Any

import numpy as np

from ._core import InputError, solve


def _rest_point(scene: str) -> np.ndarray:
    try:
        with open(scene, "rb") as f:
            doc = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{scene}: {e}") from None
    point = doc.get("probe", {}).get("point")
    if point is None or len(point) != 3:
        raise InputError(f"{scene}: [probe] point: expected 3 numbers (the probe's rest position)")
    return np.asarray(point, dtype=float)


def from_both_sides(scene: str, point: Any, along: Any, steps: int = 10) -> dict[str, Any]:
    """The precise force at `point` reached from `point - along` and from `point + along`.

    Each approach starts at rest and moves the probe to its start in `steps` equal moves, then
    to `point`. Returns a dict: force_minus and force_plus (N, the force felt at `point` by
    each), difference (|force_minus - force_plus|, N), largest (the larger |force|, N) and
    converged (both solves converged at `point`).
    """
    p = np.asarray(point, dtype=float).reshape(3)
    d = np.asarray(along, dtype=float).reshape(3)
    if not np.all(np.isfinite(p)) or not np.all(np.isfinite(d)) or not np.any(d):
        raise InputError("from_both_sides: point and along must be finite, along not zero")
    if steps < 1:
        raise InputError(f"from_both_sides: steps must be >= 1 (got {steps})")
    rest = _rest_point(scene)
    result: dict[str, Any] = {}
    converged = True
    for name, start in (("force_minus", p - d), ("force_plus", p + d)):
        path = [rest + (start - rest) * (k / steps) for k in range(1, steps + 1)] + [p]
        r = solve(scene, np.array(path))
        result[name] = np.asarray(r["force"][-1], dtype=float)
        converged = converged and bool(r["converged"][-1])
    result["difference"] = float(np.linalg.norm(result["force_minus"] - result["force_plus"]))
    result["largest"] = float(max(np.linalg.norm(result["force_minus"]),
                                  np.linalg.norm(result["force_plus"])))
    result["converged"] = converged
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python3 -m hapstate.equilibria",
        description="Solve a probe position reached from either side (docs/certificate.md, "
        "\"When it is not good enough\"): two different forces are two equilibria, a jump "
        "no grid spacing or refinement depth removes.")
    ap.add_argument("scene", help="scene file (TOML)")
    ap.add_argument("point", type=float, nargs=3, metavar=("X", "Y", "Z"),
                    help="probe position, mesh units")
    ap.add_argument("--along", type=float, nargs=3, metavar=("DX", "DY", "DZ"), required=True,
                    help="the approach: from POINT - ALONG and from POINT + ALONG (mesh units)")
    ap.add_argument("--steps", type=int, default=10,
                    help="moves from rest to each approach's start (default 10)")
    ap.add_argument("--tolerance", type=float, default=0.01,
                    help="a difference above this fraction of the larger force counts as two "
                    "equilibria (default 0.01)")
    args = ap.parse_args(argv)
    try:
        r = from_both_sides(args.scene, args.point, args.along, args.steps)
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    mn = 1e3 * r["force_minus"]
    pl = 1e3 * r["force_plus"]
    print(f"from -along: ({mn[0]:.4f}, {mn[1]:.4f}, {mn[2]:.4f}) mN")
    print(f"from +along: ({pl[0]:.4f}, {pl[1]:.4f}, {pl[2]:.4f}) mN")
    share = r["difference"] / r["largest"] if r["largest"] > 0 else 0.0
    print(f"difference {1e3 * r['difference']:.4f} mN ({100 * share:.2f} % of the larger force)")
    if not r["converged"]:
        print("not decided: a solve did not converge at the position")
        return 3
    if share > args.tolerance:
        print("two equilibria: the force jumps near here (no grid spacing or refinement depth "
              "removes that error; docs/certificate.md)")
    else:
        print("one equilibrium here (from these two sides)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
