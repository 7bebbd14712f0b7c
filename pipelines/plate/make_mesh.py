#!/usr/bin/env python3
"""Writes plate.msh (Gmsh 2.2 ASCII): a 4 x 4 x 0.2 plate (mesh units: cm), mid-plane z = 0, of
10 x 10 x 1 cubes, each split into 6 positively oriented tetrahedra along its main diagonal
(242 nodes, 600 tets).
Run once; the output is committed. Usage: make_mesh.py [OUT]"""
import itertools
import sys

NX, NY, NZ = 10, 10, 1
SIZE = (4.0, 4.0, 0.2)
Z0 = -0.1


def node_id(i, j, k):
    return (k * (NY + 1) + j) * (NX + 1) + i


def det(a, b, c, d):
    u = [b[n] - a[n] for n in range(3)]
    v = [c[n] - a[n] for n in range(3)]
    w = [d[n] - a[n] for n in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "plate.msh"
    nodes = []
    for k in range(NZ + 1):
        for j in range(NY + 1):
            for i in range(NX + 1):
                nodes.append((SIZE[0] * i / NX, SIZE[1] * j / NY, Z0 + SIZE[2] * k / NZ))
    tets = []
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                for perm in itertools.permutations(range(3)):
                    corner = [0, 0, 0]
                    path = [tuple(corner)]
                    for axis in perm:
                        corner[axis] = 1
                        path.append(tuple(corner))
                    ids = [node_id(i + a, j + b, k + c) for a, b, c in path]
                    if det(*(nodes[n] for n in ids)) < 0:
                        ids[2], ids[3] = ids[3], ids[2]
                    tets.append(ids)
    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for n, (x, y, z) in enumerate(nodes):
            f.write("%d %.17g %.17g %.17g\n" % (n + 1, x, y, z))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tets))
        for e, t in enumerate(tets):
            f.write("%d 4 2 1 1 %s\n" % (e + 1, " ".join(str(n + 1) for n in t)))
        f.write("$EndElements\n")


if __name__ == "__main__":
    main()
