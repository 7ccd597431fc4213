#!/usr/bin/env python3
"""Crossed-triangle mesh of a vertical cut (Gmsh 2.2 ASCII), for examples/vertical_cut.

    make_mesh.py H h OUT.msh [--extrude T]

The ground behind the cut stands H above the toe; the face is vertical at x = 2H; the
soil goes on H below the toe and 2H in front of the face. Every h x h cell is split in
four triangles around its centre ("union jack"): linear triangles arranged so lock far
less under the isochoric plastic flow of a phi = 0 soil than an unstructured mesh.
Groups: surface "soil"; curves "base" (y = 0), "left" (x = 0), "right" (x = 4H),
"ground" (the free surface).

With --extrude T, the same section as a 3D mesh one layer of thickness T thick: the plane's
(x, y) is (x, z), the layer spans 0 <= y <= T, and each triangle's prism is split into
three tetrahedra by its vertex numbers (the diagonal of every side face runs from its
lower-numbered vertex at y = 0 to the other at y = T, so neighbouring prisms conform).
Groups: volume "soil"; surfaces "base", "left", "right", "ground", "front" (y = 0) and
"back" (y = T). Between rollers on front and back it is the plane-strain cut in 3D.
"""
import sys


def write_extruded(out, nodes, tris, lines, T):
    """The section extruded one layer along y (see the module's docstring)."""
    ordered = sorted(nodes.values())
    n2 = len(ordered)
    xy = {nid: (x, y) for nid, x, y in ordered}

    def at(nid, layer):  # node id of a plane node at y = 0 (layer 0) or y = T (layer 1)
        return nid + layer * n2

    def point(nid):
        base = nid - n2 if nid > n2 else nid
        x, z = xy[base]
        return (x, T if nid > n2 else 0.0, z)

    def right_handed(t):
        p = [point(v) for v in t]
        e = [[p[k][d] - p[0][d] for d in range(3)] for k in (1, 2, 3)]
        det = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
               + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]))
        return t if det > 0 else (t[0], t[2], t[1], t[3])

    tets, faces = [], []  # faces: (physical tag, n1, n2, n3)
    for tri in tris:
        a, b, c = sorted(tri)
        a0, b0, c0, a1, b1, c1 = at(a, 0), at(b, 0), at(c, 0), at(a, 1), at(b, 1), at(c, 1)
        tets += [right_handed(t) for t in ((a0, b0, c0, c1), (a0, b0, b1, c1), (a0, a1, b1, c1))]
        faces += [(6, a0, b0, c0), (7, a1, b1, c1)]  # front, back
    for tag, p, q in lines:  # each boundary segment's side face, split along its diagonal
        lo, hi = min(p, q), max(p, q)
        faces += [(tag, at(lo, 0), at(hi, 0), at(hi, 1)), (tag, at(lo, 0), at(lo, 1), at(hi, 1))]
    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        f.write('$PhysicalNames\n7\n3 1 "soil"\n2 2 "base"\n2 3 "left"\n2 4 "right"\n2 5 "ground"\n'
                '2 6 "front"\n2 7 "back"\n$EndPhysicalNames\n')
        f.write(f"$Nodes\n{2 * n2}\n")
        for nid in range(1, 2 * n2 + 1):
            x, y, z = point(nid)
            f.write(f"{nid} {x:.12g} {y:.12g} {z:.12g}\n")
        f.write("$EndNodes\n")
        f.write(f"$Elements\n{len(faces) + len(tets)}\n")
        k = 1
        for tag, p, q, r in faces:
            f.write(f"{k} 2 2 {tag} {tag} {p} {q} {r}\n")
            k += 1
        for t in tets:
            f.write(f"{k} 4 2 1 1 {t[0]} {t[1]} {t[2]} {t[3]}\n")
            k += 1
        f.write("$EndElements\n")


def main() -> int:
    args = sys.argv[1:]
    extrude = None
    if "--extrude" in args:
        k = args.index("--extrude")
        extrude = float(args[k + 1])
        del args[k:k + 2]
    H, h, out = float(args[0]), float(args[1]), args[2]
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
    if extrude is not None:
        write_extruded(out, nodes, tris, lines, extrude)
        return 0
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
