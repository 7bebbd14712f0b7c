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


# Below this difference (N) two forces are the same whatever --tolerance says: the solver's
# residual tolerance (1e-8 relative) leaves far less, and a grazing contact's forces are
# round-off apart.
_ABSOLUTE_FLOOR = 1e-7


def _read_scene(scene: Any) -> dict[str, Any]:
    try:
        with open(scene, "rb") as f:
            return tomllib.load(f)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise InputError(f"{scene}: {e}") from None


def _vector(scene: Any, where: str, value: Any) -> np.ndarray:
    """`value` as 3 finite numbers (a number is taken for all three), else InputError."""
    try:
        v = np.broadcast_to(np.asarray(value, dtype=float), (3,)).copy()
    except (ValueError, TypeError):
        v = np.full(3, np.nan)
    if not np.all(np.isfinite(v)):
        raise InputError(f"{scene}: {where}: expected 3 finite numbers (got {value!r})")
    return v


def _rest_point(scene: Any) -> np.ndarray:
    doc = _read_scene(scene)
    probe = doc.get("probe", {})
    if probe.get("mode") != "contact":
        raise InputError(f"{scene}: [probe] mode: this check is for a contact probe (got "
                         f"{probe.get('mode')!r})")
    if "point" not in probe:
        raise InputError(f"{scene}: [probe] point: expected 3 numbers (the probe's rest position)")
    return _vector(scene, "[probe] point", probe["point"])


def from_both_sides(scene: Any, point: Any, along: Any, steps: int = 10) -> dict[str, Any]:
    """The precise force at `point` reached by way of `point - along` and of `point + along`.

    For a contact probe. Each approach starts at rest, moves the probe to its start in `steps`
    equal moves and slides it to `point` in `steps` more. Returns a dict: force_minus and
    force_plus (N, the force felt at `point` by each; NaN where that approach's last solve failed,
    which leaves the body where it was), started_minus and started_plus (whether that approach's
    start was reached: every solve from rest converged), converged_minus and converged_plus
    (whether every solve of that approach converged, at `point` too), difference
    (|force_minus - force_plus|, N; NaN unless both converged) and largest (the larger |force|
    of those that converged, N).
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
        last_ok = bool(r["converged"][-1])
        force = np.asarray(r["force"][-1], dtype=float)
        result["force_" + side] = force if last_ok else np.full(3, np.nan)
        result["started_" + side] = bool(np.all(r["converged"][:steps]))
        result["converged_" + side] = bool(np.all(r["converged"]))
    fm, fp = result["force_minus"], result["force_plus"]
    result["difference"] = float(np.linalg.norm(fm - fp))
    norms = [float(np.linalg.norm(f)) for f in (fm, fp) if np.all(np.isfinite(f))]
    result["largest"] = max(norms) if norms else float("nan")
    return result


def _half_spacing(scene: Any) -> np.ndarray:
    """Half the scene's grid spacing per axis: [grid] spacing, or box and dims."""
    grid = _read_scene(scene).get("grid", {})
    if "spacing" in grid:
        h = _vector(scene, "[grid] spacing", grid["spacing"])
    elif "dims" in grid and "box" in grid:
        try:
            box = np.asarray(grid["box"], dtype=float).reshape(2, 3)
        except (ValueError, TypeError):
            raise InputError(f"{scene}: [grid] box: expected [[x, y, z], [x, y, z]]") from None
        dims = _vector(scene, "[grid] dims", grid["dims"])
        if not np.all(dims >= 2):
            raise InputError(f"{scene}: [grid] dims: expected at least 2 per axis (got {dims})")
        h = (box[1] - box[0]) / (dims - 1)
    else:
        raise InputError(f"{scene}: [grid]: no spacing (nor box and dims): give --along")
    if not np.all(np.isfinite(h)) or not np.all(h > 0):
        raise InputError(f"{scene}: [grid]: the spacing is not positive on every axis: give --along")
    return 0.5 * h


# What _verdict found at one position from one pair of approaches.
ONE, TWO, ENDS, UNDECIDED = "one equilibrium", "two equilibria", "an equilibrium ends", "undecided"


def _verdict(r: dict[str, Any], tolerance: float) -> tuple[str, str]:
    """What was found (ONE, TWO, ENDS or UNDECIDED) and the sentence that says it."""
    if not (r["started_minus"] and r["started_plus"]):
        return UNDECIDED, ("not decided: an approach did not reach its start from rest (try a "
                           "shorter --along or more --steps)")
    if r["converged_minus"] != r["converged_plus"]:
        failed = "-along" if not r["converged_minus"] else "+along"
        return ENDS, (f"likely an equilibrium ending near here: Newton failed on the approach "
                      f"from {failed} only, as it does where the state it follows ends (or a "
                      "solve that needs more --steps)")
    if not r["converged_minus"]:
        return UNDECIDED, "not decided: neither approach converged"
    if r["difference"] > max(tolerance * r["largest"], _ABSOLUTE_FLOOR):
        return TWO, "two equilibria: the force jumps near here"
    return ONE, "one equilibrium here (from these two sides)"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python3 -m hapstate.equilibria",
        description="Solve a contact probe's position reached from either side "
        "(docs/certificate.md, \"When it is not good enough\"): two different forces are two "
        "equilibria, a jump no grid spacing or refinement depth removes. Exit 0: decided, 2: bad "
        "input, 3: not decided.")
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
    if not (args.tolerance > 0 and np.isfinite(args.tolerance)):
        print(f"error: --tolerance must be a number > 0 (got {args.tolerance})", file=sys.stderr)
        return 2
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
    kinds = []
    for d, r in results:
        kind, text = _verdict(r, args.tolerance)
        kinds.append(kind)
        print(f"along ({d[0]:g}, {d[1]:g}, {d[2]:g}):")
        for side in ("minus", "plus"):
            f = 1e3 * r["force_" + side]
            sign = "-" if side == "minus" else "+"
            if np.all(np.isfinite(f)):
                print(f"  from {sign}along: ({f[0]:.4f}, {f[1]:.4f}, {f[2]:.4f}) mN")
            else:
                print(f"  from {sign}along: Newton failed: no force at the position")
        if np.isfinite(r["difference"]) and r["largest"] > 0:
            print(f"  difference {1e3 * r['difference']:.4f} mN "
                  f"({100 * r['difference'] / r['largest']:.2f} % of the larger force)")
        print(f"  {text}")
    if TWO in kinds:
        print("the force jumps near here: no grid spacing or refinement depth removes that error "
              "(docs/certificate.md, \"When it is not good enough\")")
    elif ENDS in kinds:
        print("the force likely jumps near here (an equilibrium ends): if so, no grid spacing or "
              "refinement depth removes that error (docs/certificate.md)")
    return 3 if UNDECIDED in kinds and not (TWO in kinds or ENDS in kinds) else 0


if __name__ == "__main__":
    sys.exit(main())
