#!/usr/bin/env python3
"""Writes plate.msh (Gmsh 2.2 ASCII): a 4 x 4 x 0.2 plate (mesh units: cm), mid-plane z = 0, of
10 x 10 x 1 cubes, each split into 6 positively oriented tetrahedra along its main diagonal
(242 nodes, 600 tets).
Run once; the output is committed. Usage: make_mesh.py [OUT]"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from box_mesh import write_box_msh  # noqa: E402

if __name__ == "__main__":
    write_box_msh(sys.argv[1] if len(sys.argv) > 1 else "plate.msh", (10, 10, 1), (4.0, 4.0, 0.2),
                  origin=(0.0, 0.0, -0.1))
