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
    r["difference"], r["verdict"]   # |f(-) - f(+)| in N; "one", "two", "ends" or "undecided"

From the shell (positions in mesh units, as `hapstate-inspect summary` prints them):

    PYTHONPATH=build/python /usr/bin/python3 -m hapstate.equilibria SCENE X Y Z [--along DX DY DZ]

(without --along: half the grid spacing along x, then y, then z). A short approach can miss a
range where both equilibria exist: both approaches then start on the same side of it. The solves
and the verdict are the C++ ones (hapstate._core.from_both_sides, eval/equilibria.h) that
hapstate-certify runs at its worst steps.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

import numpy as np

from ._core import InputError
from ._core import from_both_sides as _from_both_sides

# The verdicts (hapstate._core.from_both_sides' "verdict").
ONE, TWO, ENDS, UNDECIDED = "one", "two", "ends", "undecided"


def from_both_sides(scene: Any, point: Any, along: Any, steps: int = 10,
                    tolerance: float = 0.01) -> dict[str, Any]:
    """The precise force at `point` reached by way of `point - along` and of `point + along`.

    Each approach starts at rest, moves the probe to its start in `steps` equal moves and slides
    it to `point` in `steps` more. Returns a dict: force_minus and force_plus (N, the force felt
    at `point` by each; NaN where that approach's last solve failed, which leaves the body where
    it was), started_minus and started_plus (whether that approach's start was reached: every
    solve from rest converged), converged_minus and converged_plus (whether every solve of that
    approach converged, at `point` too), difference (|force_minus - force_plus|, N; NaN unless
    both converged), largest (the larger |force| of those that converged, N) and verdict (ONE,
    TWO: the forces differ by more than tolerance x largest and 1e-7 N, ENDS: Newton failed on
    one side only, UNDECIDED).
    """
    if along is None:
        raise InputError("from_both_sides: along: expected 3 numbers (hapstate._core."
                         "from_both_sides takes None for the three default approaches)")
    return _from_both_sides(scene, point, along, steps, tolerance)[0]


def _sentence(r: dict[str, Any]) -> str:
    """What a verdict says, in words."""
    v = r["verdict"]
    if v == TWO:
        return "two equilibria: the force jumps near here"
    if v == ENDS:
        failed = "-along" if not r["converged_minus"] else "+along"
        return (f"likely an equilibrium ending near here: Newton failed on the approach from "
                f"{failed} only, as it does where the state it follows ends (or a solve that "
                "needs more --steps)")
    if v == ONE:
        return "one equilibrium here (from these two sides)"
    if not (r["started_minus"] and r["started_plus"]):
        return ("not decided: an approach did not reach its start from rest (try a shorter "
                "--along or more --steps)")
    return "not decided: neither approach converged"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python3 -m hapstate.equilibria",
        description="Solve a probe's position reached from either side (docs/certificate.md, "
        "\"When it is not good enough\"): two different forces are two equilibria, a jump no "
        "grid spacing or refinement depth removes. Exit 0: decided, 2: bad input, 3: not decided.")
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
        results = _from_both_sides(args.scene, args.point, args.along, args.steps,
                                   args.tolerance)
    except (InputError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    kinds = []
    for r in results:
        kinds.append(r["verdict"])
        d = r["along"]
        print(f"along ({d[0]:g}, {d[1]:g}, {d[2]:g}):")
        for side in ("minus", "plus"):
            f = 1e3 * np.asarray(r["force_" + side])
            sign = "-" if side == "minus" else "+"
            if np.all(np.isfinite(f)):
                print(f"  from {sign}along: ({f[0]:.4f}, {f[1]:.4f}, {f[2]:.4f}) mN")
            else:
                print(f"  from {sign}along: Newton failed: no force at the position")
        if np.isfinite(r["difference"]) and r["largest"] > 0:
            print(f"  difference {1e3 * r['difference']:.4f} mN "
                  f"({100 * r['difference'] / r['largest']:.2f} % of the larger force)")
        print(f"  {_sentence(r)}")
    if TWO in kinds:
        print("the force jumps near here: no grid spacing or refinement depth removes that error "
              "(docs/certificate.md, \"When it is not good enough\")")
    elif ENDS in kinds:
        print("the force likely jumps near here (an equilibrium ends): if so, no grid spacing or "
              "refinement depth removes that error (docs/certificate.md)")
    return 3 if UNDECIDED in kinds and not (TWO in kinds or ENDS in kinds) else 0


if __name__ == "__main__":
    sys.exit(main())
