"""A box of n[0] x n[1] x n[2] cubes, each split into 6 positively oriented tetrahedra along its
main diagonal, written as Gmsh 2.2 ASCII: the bundled structured meshes (beam, plate) use it."""
import itertools


def _det(a, b, c, d):
    u = [b[n] - a[n] for n in range(3)]
    v = [c[n] - a[n] for n in range(3)]
    w = [d[n] - a[n] for n in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def write_box_msh(out, n, size, origin=(0.0, 0.0, 0.0)):
    nx, ny, nz = n

    def node_id(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    nodes = []
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                nodes.append((origin[0] + size[0] * i / nx, origin[1] + size[1] * j / ny,
                              origin[2] + size[2] * k / nz))
    tets = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                for perm in itertools.permutations(range(3)):
                    corner = [0, 0, 0]
                    path = [tuple(corner)]
                    for axis in perm:
                        corner[axis] = 1
                        path.append(tuple(corner))
                    ids = [node_id(i + a, j + b, k + c) for a, b, c in path]
                    if _det(*(nodes[m] for m in ids)) < 0:
                        ids[2], ids[3] = ids[3], ids[2]
                    tets.append(ids)
    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for m, (x, y, z) in enumerate(nodes):
            f.write("%d %.17g %.17g %.17g\n" % (m + 1, x, y, z))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tets))
        for e, t in enumerate(tets):
            f.write("%d 4 2 1 1 %s\n" % (e + 1, " ".join(str(m + 1) for m in t)))
        f.write("$EndElements\n")
