#!/usr/bin/env python3
"""Writes the plate meshes (Gmsh 2.2 ASCII): a 4 x 4 x 0.2 plate (mesh units: cm), mid-plane
z = 0, of cubes, each split into 6 positively oriented tetrahedra along its main diagonal.
  plate.msh         20 x 20 x 1 cubes of 0.2 cm (882 nodes, 2 400 tets): the bundled scene.
  plate_coarse.msh  10 x 10 x 1 cubes of 0.4 cm (242 nodes, 600 tets): the tests' plate.
A frictionless sphere feels the facets of the P1 surface; with 0.4 cm facets under a 0.2 cm grid
the interpolated force misses part of that ripple (docs/contact.md, "Accuracy and the mesh").
Run once; the outputs are committed. Usage: make_mesh.py [DIR]"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from box_mesh import write_box_msh  # noqa: E402

if __name__ == "__main__":
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    write_box_msh(str(out / "plate.msh"), (20, 20, 1), (4.0, 4.0, 0.2), origin=(0.0, 0.0, -0.1))
    write_box_msh(str(out / "plate_coarse.msh"), (10, 10, 1), (4.0, 4.0, 0.2),
                  origin=(0.0, 0.0, -0.1))
