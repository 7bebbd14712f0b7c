"""hapstate from Python: a precomputed state space and its haptic playback (docs/python.md).

    import hapstate
    pb = hapstate.Playback("pipelines/liver/state/playback.bin")
    cursor = pb.cursor("hermite")
    forces = cursor.force(path)            # (n, 3) N along an (n, 3) path, the loop in C++
    cat = hapstate.Catalogue("pipelines/liver/state")
    rows = cat.configurations()            # dict of NumPy arrays
    exact = hapstate.solve("pipelines/liver/scene.toml", path)["force"]

Positions are in mesh units (the scene's), forces in N, stiffness in N per mesh unit. Errors
are hapstate.InputError (bad input, a ValueError) and hapstate.EnvironmentError (I/O, an
OSError), with the command-line tools' messages.
"""

from ._core import (Catalogue, Cursor, EnvironmentError, InputError, Playback,  # noqa: F401
                    solve)

__all__ = ["Playback", "Cursor", "Catalogue", "solve", "InputError", "EnvironmentError"]
