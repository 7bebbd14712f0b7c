#!/usr/bin/env python3
"""Writes beam.msh (Gmsh 2.2 ASCII): a 4 x 1 x 1 beam (mesh units: cm) of 8 x 2 x 2 cubes, each
split into 6 positively oriented tetrahedra along its main diagonal (81 nodes, 192 tets).
Run once; the output is committed. Usage: make_mesh.py [OUT]"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from box_mesh import write_box_msh  # noqa: E402

if __name__ == "__main__":
    write_box_msh(sys.argv[1] if len(sys.argv) > 1 else "beam.msh", (8, 2, 2), (4.0, 1.0, 1.0))
