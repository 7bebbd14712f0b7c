"""The tutorial of docs/python.md on the bundled liver: load its playback file, query the haptic
cursor along a path, compare with the precise solver, look at the catalogue, and plot the force
against the probe's position.

Run from the repository root after README command 1 (which precomputes pipelines/liver/state):
    PYTHONPATH=build/python /usr/bin/python3 python/examples/liver_tour.py [OUT_DIR]
"""

import pathlib
import sys
import time

import numpy as np

import hapstate

state = pathlib.Path("pipelines/liver/state")
scene = pathlib.Path("pipelines/liver/scene.toml")
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")
out.mkdir(parents=True, exist_ok=True)

# 1. The playback file: memory-mapped, read-only.
pb = hapstate.Playback(state / "playback.bin")
print(pb)
print("grid:", pb.grid_dims, "check-points,", pb.grid_spacing, "cm apart; probe at rest",
      pb.probe_rest)

# 2. A path: the grabbed point pulled up (+z) from rest to the top of the workspace and back,
# 400 positions, as a device would sample it.
top = pb.grid_origin[2] + (pb.grid_lo[2] + pb.grid_dims[2] - 1) * pb.grid_spacing[2]
s = np.concatenate([np.linspace(0, 1, 200), np.linspace(1, 0, 200)])
path = pb.probe_rest + np.outer(s, [0.0, 0.0, top - pb.probe_rest[2]])

# 3. The haptic cursor: the loop runs in C++, one force() per position, in order; the cursor
# keeps its place between calls (the first call also walks the first cells from rest).
cursor = pb.cursor("hermite")
start = time.perf_counter()
force_up = cursor.force(path[:200])
elapsed = time.perf_counter() - start
u = cursor.deform()  # the view nodes' displacements where the cursor is: at the top
print(f"at the top: largest displacement {np.linalg.norm(u, axis=1).max():.4f} cm, "
      f"stiffness (N/cm)\n{cursor.stiffness(path[199])}")
force = np.vstack([force_up, cursor.force(path[200:])])  # and back down, the same cursor
print(f"hermite cursor: 200 queries in {1e3 * elapsed:.2f} ms; largest |f| "
      f"{np.linalg.norm(force, axis=1).max():.4f} N")
trilinear = pb.cursor("trilinear").force(path)

# 4. The precise solver at every 20th position of the way up (a few seconds).
up = path[:200:20]
exact = hapstate.solve(scene, up)
assert exact["converged"].all(), exact["failure"]
largest = np.linalg.norm(exact["force"], axis=1).max()
for name, f in (("hermite", force[:200:20]), ("trilinear", trilinear[:200:20])):
    error = np.linalg.norm(f - exact["force"], axis=1).max() / largest
    print(f"{name}: largest force error on the way up {100 * error:.3g} % of {largest:.4f} N")

# 5. The catalogue: what the precomputation stored.
catalogue = hapstate.Catalogue(state)
configurations = catalogue.configurations()
levels = np.bincount(configurations["checkpoint"])
print(f"catalogue: {len(configurations['id'])} configurations on {np.count_nonzero(levels)} "
      f"check-points, at most {levels.max()} levels; summary keys: "
      f"{', '.join(catalogue.summary())}")

# 6. Force against position.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

height = path[:200, 2] - pb.probe_rest[2]
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(height, force[:200, 2], label="Hermite cursor (up)")
ax.plot(path[200:, 2] - pb.probe_rest[2], force[200:, 2], "--", label="Hermite cursor (down)")
ax.plot(height, trilinear[:200, 2], ":", label="trilinear cursor (up)")
ax.plot(up[:, 2] - pb.probe_rest[2], exact["force"][:, 2], "o", label="precise solver")
ax.set_xlabel("probe height above rest (cm)")
ax.set_ylabel("force z (N)")
ax.set_title("Bundled liver: pulling the grabbed point up")
ax.legend()
fig.tight_layout()
fig.savefig(out / "liver_force.png", dpi=110)
print("wrote", out / "liver_force.png")
