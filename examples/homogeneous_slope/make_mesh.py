#!/usr/bin/env python3
"""Crossed-triangle mesh of the homogeneous slope (Gmsh 2.2 ASCII), for examples/homogeneous_slope.

    make_mesh.py h OUT.msh

The profile of slope.geo: 27 m x 6.5 m, base y = 0, ground at y = 6.5 up to the crest (9, 6.5),
the 1:2 face down to the toe (18, 2), then y = 2 to x = 27. A mapped mesh: columns of width h
from x = 0 to 27 (h must divide 9, so that x = 9 and x = 18 are column lines: 1, 0.5, 0.25 ...),
and in every column the same number of rows, ny = ceil(6.5 / h) (no cell taller than h), spaced
evenly from the base to the ground at that x; every node of a column line is shared by the
cells on both sides (a conforming mesh). Behind the crest the cells are about h x h, in front
of the toe h x 2/ny (flatter), trapezoids on the face.

Every cell is split in four triangles around the point where its diagonals cross ("union
jack", crossed triangles): taken in pairs the four are both diagonal splits of the cell, which
keeps one of the four incompressibility constraints dependent (on a trapezoid too; its
centroid would not), so linear triangles in this pattern lock far less under plastic flow
than an unstructured mesh of them (examples/vertical_cut).

Groups as slope.geo's under gmsh: surface "soil" (1); curves "base" (2, y = 0), "right" (3,
x = 27), "left" (4, x = 0), "ground" (5, the ground surface, face included).

The script checks what it writes (counter-clockwise triangles, the profile's area, the
boundary edges of the triangles exactly the group lines, each in its group) and prints
the counts.
"""
import math
import sys

W, HT = 27.0, 6.5             # model width and height (the ground behind the crest)
XC, XT, YT = 9.0, 18.0, 2.0   # crest x, toe x, ground height in front of the toe
TAGS = {"soil": 1, "base": 2, "right": 3, "left": 4, "ground": 5}


def ground(x):
    """Height of the ground surface at x."""
    if x <= XC:
        return HT
    if x >= XT:
        return YT
    return HT + (x - XC) * (YT - HT) / (XT - XC)


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    h, out = float(sys.argv[1]), sys.argv[2]
    nx = round(W / h)
    nc = round(XC / h)
    assert h > 0 and abs(nc * h - XC) < 1e-9 * XC, "h must divide 9 (x = 9 and x = 18 column lines)"
    ny = math.ceil(HT / h - 1e-9)

    xs = [i * h for i in range(nx + 1)]
    xs[nc], xs[2 * nc], xs[nx] = XC, XT, W  # the kinks and the right side exactly
    coords = []                 # node id - 1 -> (x, y)

    def add(x, y):
        coords.append((x, y))
        return len(coords)

    grid = [[add(x, j * ground(x) / ny) for j in range(ny + 1)] for x in xs]  # grid[i][j]

    tris = []
    for i in range(nx):
        for j in range(ny):
            a, b, c, d = grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]  # counter-clockwise
            (xa, ya), (xb, yb), (xc, yc), (xd, yd) = (coords[k - 1] for k in (a, b, c, d))
            # where the diagonals a-c and b-d cross
            den = (xc - xa) * (yd - yb) - (yc - ya) * (xd - xb)
            t = ((xb - xa) * (yd - yb) - (yb - ya) * (xd - xb)) / den
            m = add(xa + t * (xc - xa), ya + t * (yc - ya))
            tris += [(a, b, m), (b, c, m), (c, d, m), (d, a, m)]

    lines = []  # (physical tag, n1, n2)
    lines += [(TAGS["base"], grid[i][0], grid[i + 1][0]) for i in range(nx)]
    lines += [(TAGS["right"], grid[nx][j], grid[nx][j + 1]) for j in range(ny)]
    lines += [(TAGS["left"], grid[0][j + 1], grid[0][j]) for j in range(ny)]
    lines += [(TAGS["ground"], grid[i + 1][ny], grid[i][ny]) for i in range(nx)]  # right to left, as slope.geo
    check(coords, tris, lines)

    with open(out, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        names = sorted(TAGS.items(), key=lambda kv: kv[1])
        f.write(f"$PhysicalNames\n{len(names)}\n")
        for name, tag in names:
            f.write(f'{2 if name == "soil" else 1} {tag} "{name}"\n')
        f.write("$EndPhysicalNames\n")
        f.write(f"$Nodes\n{len(coords)}\n")
        for k, (x, y) in enumerate(coords, 1):
            f.write(f"{k} {x:.12g} {y:.12g} 0\n")
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
    print(f"{out}: h = {h:g} m, {nx} columns x {ny} rows, {len(coords)} nodes, {len(tris)} triangles, "
          f"{len(lines)} boundary lines")
    return 0


def check(coords, tris, lines):
    """Counter-clockwise triangles, the profile's area, group lines = the triangles' boundary edges."""
    xy = lambda k: coords[k - 1]
    area = 0.0
    for t in tris:
        (x1, y1), (x2, y2), (x3, y3) = map(xy, t)
        a2 = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1)
        assert a2 > 0, f"triangle {t} is not counter-clockwise (2A = {a2})"
        area += a2 / 2
    profile = XC * HT + (XT - XC) * (HT + YT) / 2 + (W - XT) * YT  # 114.75 m^2
    assert abs(area - profile) < 1e-9 * profile, f"area {area} != {profile}"
    count = {}
    for t in tris:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = frozenset(e)
            count[key] = count.get(key, 0) + 1
    assert max(count.values()) <= 2, "an edge shared by more than two triangles"
    boundary = {e for e, c in count.items() if c == 1}
    listed = [frozenset((p, q)) for _, p, q in lines]
    assert len(set(listed)) == len(listed) and set(listed) == boundary, "group lines != boundary edges"
    on = {
        "base": lambda x, y: abs(y) < 1e-9,
        "left": lambda x, y: abs(x) < 1e-9,
        "right": lambda x, y: abs(x - W) < 1e-9,
        "ground": lambda x, y: abs(y - ground(x)) < 1e-9,
    }
    length = {name: 0.0 for name in on}
    for tag, p, q in lines:
        name = next(n for n, v in TAGS.items() if v == tag)
        assert on[name](*xy(p)) and on[name](*xy(q)), f"line {p}-{q} is not on the {name}"
        length[name] += math.dist(xy(p), xy(q))
    face = math.hypot(XT - XC, HT - YT)
    want = {"base": W, "left": HT, "right": YT, "ground": XC + face + (W - XT)}
    for name in on:
        assert abs(length[name] - want[name]) < 1e-9 * want[name], f"{name}: length {length[name]} != {want[name]}"


if __name__ == "__main__":
    sys.exit(main())
