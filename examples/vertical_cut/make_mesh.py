#!/usr/bin/env python3
"""Crossed-triangle mesh of a vertical cut (Gmsh 2.2 ASCII), for examples/vertical_cut.

    make_mesh.py H h OUT.msh

The ground behind the cut stands H above the toe; the face is vertical at x = 2H; the
soil goes on H below the toe and 2H in front of the face. Every h x h cell is split in
four triangles around its centre ("union jack"): linear triangles arranged so lock far
less under the isochoric plastic flow of a phi = 0 soil than an unstructured mesh.
Groups: surface "soil"; curves "base" (y = 0), "left" (x = 0), "right" (x = 4H),
"ground" (the free surface).
"""
import sys


def main() -> int:
    H, h, out = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    n = round(H / h)
    assert abs(n * h - H) < 1e-9 * H, "h must divide H"
    nodes = {}

    def node(x, y):
        key = (round(x / h * 2), round(y / h * 2))  # half-cell lattice
        if key not in nodes:
            nodes[key] = (len(nodes) + 1, x, y)
        return nodes[key][0]

    tris = []
    # cells: foundation [0, 4H] x [0, H] and the ground behind the face [0, 2H] x [H, 2H]
    cells = [(i, j) for j in range(n) for i in range(4 * n)] + [(i, j) for j in range(n, 2 * n) for i in range(2 * n)]
    for i, j in cells:
        x0, y0 = i * h, j * h
        a, b, c, d = node(x0, y0), node(x0 + h, y0), node(x0 + h, y0 + h), node(x0, y0 + h)
        m = node(x0 + h / 2, y0 + h / 2)
        tris += [(a, b, m), (b, c, m), (c, d, m), (d, a, m)]
    lines = []  # (physical tag, n1, n2)
    for i in range(4 * n):
        lines.append((2, node(i * h, 0), node((i + 1) * h, 0)))  # base
    for j in range(2 * n):
        lines.append((3, node(0, j * h), node(0, (j + 1) * h)))  # left
    for j in range(n):
        lines.append((4, node(4 * n * h, j * h), node(4 * n * h, (j + 1) * h)))  # right
    for i in range(2 * n):
        lines.append((5, node(i * h, 2 * H), node((i + 1) * h, 2 * H)))  # ground behind the crest
    for j in range(n, 2 * n):
        lines.append((5, node(2 * H, j * h), node(2 * H, (j + 1) * h)))  # face
    for i in range(2 * n, 4 * n):
        lines.append((5, node(i * h, H), node((i + 1) * h, H)))  # ground in front of the toe
    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        f.write('$PhysicalNames\n5\n2 1 "soil"\n1 2 "base"\n1 3 "left"\n1 4 "right"\n1 5 "ground"\n$EndPhysicalNames\n')
        f.write(f"$Nodes\n{len(nodes)}\n")
        for nid, x, y in sorted(nodes.values()):
            f.write(f"{nid} {x:.12g} {y:.12g} 0\n")
        f.write("$EndNodes\n")
        f.write(f"$Elements\n{len(lines) + len(tris)}\n")
        k = 1
        for tag, p, q in lines:
            f.write(f"{k} 1 2 {tag} {tag} {p} {q}\n")
            k += 1
        for p, q, r in tris:
            f.write(f"{k} 2 2 1 1 {p} {q} {r}\n")
            k += 1
        f.write("$EndElements\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
