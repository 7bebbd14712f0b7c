"""Fixtures of the Python tests: the build (HAPSTATE_BUILD_DIR, set by ctest), and two small
states made by `hapstate run` once per session: the beam grabbed at its free end and the beam
touched by a sphere (each about a second), with hapstate-eval's 30-step path on each."""

import csv
import os
import pathlib
import subprocess

import sys

import numpy as np
import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("HAPSTATE_BUILD_DIR", SOURCE / "build"))
TOOLS = BUILD / "tools"
sys.path.insert(0, str(SOURCE / "tests/blobs"))  # h5py_vectors: an independent blob reader
os.environ.setdefault("HDF5_PLUGIN_PATH", str(BUILD / "plugins"))  # our zstd filter, for h5py
SCENES = {"grab": SOURCE / "pipelines/beam/scene.toml",
          "contact": SOURCE / "tests/scenes/beam_contact.toml"}


class EvalPath:
    """hapstate-eval's CSV: the path, the precise forces and each scheme's played-back forces."""

    def __init__(self, file: pathlib.Path):
        rows = list(csv.DictReader(open(file)))
        col = lambda names: np.array([[float(r[n]) for n in names] for r in rows])  # noqa: E731
        self.path = col(["x", "y", "z"])
        self.exact = col(["fx_exact", "fy_exact", "fz_exact"])
        self.hermite = col(["hermite_fx", "hermite_fy", "hermite_fz"])
        self.trilinear = col(["trilinear_fx", "trilinear_fy", "trilinear_fz"])
        self.largest = float(np.linalg.norm(self.exact, axis=1).max())


class State:
    def __init__(self, kind: str, root: pathlib.Path):
        self.kind = kind
        self.scene = SCENES[kind]
        self.dir = root / "state"
        subprocess.run([TOOLS / "hapstate", "run", self.scene, "--state", self.dir, "-q"],
                       check=True, capture_output=True)
        subprocess.run([TOOLS / "hapstate-eval", "--state", self.dir, "--steps", "30", "--seed",
                        "2", "--csv", root / "eval.csv", "--no-plot"],
                       check=True, capture_output=True)
        self.eval = EvalPath(root / "eval.csv")


@pytest.fixture(scope="session", params=["grab", "contact"])
def state(request, tmp_path_factory) -> State:
    return State(request.param, tmp_path_factory.mktemp(request.param))


@pytest.fixture(scope="session")
def grab_state(tmp_path_factory) -> State:
    return State("grab", tmp_path_factory.mktemp("grab-only"))
