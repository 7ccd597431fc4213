#!/usr/bin/python3
"""Bishop's simplified method of slices with a search over circular slip surfaces.

    bishop.py                       the homogeneous slope of this example (README.md)
    bishop.py --check               self-check against published results (asserts within 1 %)
    bishop.py --ground "0,6.5 9,6.5 18,2 27,2" --gamma 16 --c 5 --phi 20 [--floor 0]
              [--divisor D] [--circle XC,YC,R] [--slices N] [--grid N]

A homogeneous, dry slope: a ground polyline (x increasing; the slope may face +x or -x),
unit weight gamma, cohesion c, friction angle phi (any consistent units: kN/m^3, kPa, m;
or pcf, psf, ft). `--divisor D` divides c and tan(phi) by D before the analysis (the
strength reduction of `dsdem stability`): the Bishop factor of the reduced soil is then
FS / D for every circle. `--floor Y` forbids circles that go below the elevation Y (a
rigid base, as the fixed base of the finite-element model).

Bishop's simplified method (Bishop 1955): moment equilibrium about the centre of the
circle, interslice forces horizontal, so

    F = sum[(c b + W tan(phi)) / m_alpha] / sum[W sin(alpha)],
    m_alpha = cos(alpha) + sin(alpha) tan(phi) / F,

solved by fixed-point iteration (b: slice width, W: slice weight, alpha: inclination of
the slice base). Slices are vertical, of equal width, with extra boundaries at the
polyline's vertices (so the top of each slice is straight); the weight is gamma times the
slice's mid-height times its width. The ordinary (Fellenius) factor
sum[c l + W cos(alpha) tan(phi)] / sum[W sin(alpha)] is printed alongside.

Search: a grid of centres over the slope and, for each centre, circles tangent to a range
of elevations (from the floor, or one slope height below the toe, up to the crest) plus
the circle through the toe; then a Nelder-Mead refinement of (xc, yc, R) from the best few
circles of the grid. Circles whose slip mass reaches either end of the ground polyline, or
whose centre lies below the ground they cut, are discarded; so are circles with
m_alpha <= 0 on any slice.

Self-check (`--check`, every result within 1 %):
  1. Fredlund & Krahn (1977), "Comparison of slope stability methods of analysis",
     Can. Geotech. J. 14(3), 429-439, example case 1: a 2:1 slope 40 ft high,
     c' = 600 psf, phi' = 20 deg, gamma = 120 pcf, the circle of centre (120, 90) ft and
     radius 80 ft: Bishop's simplified 2.080, ordinary method 1.928 (the published
     table as reproduced by the MacSlope verification page, macslope.com/verification/
     fredlund-example). The ground is (0, 60), (60, 60), (140, 20), (170, 20) ft
     (crest at x = 60, toe at x = 140, the coordinates in which that centre is given).
  2. This example: H = 4.5 m, 1:2, gamma = 16 kN/m^3, c = 5 kPa, phi = 20 deg: the
     minimum over circles is Bishop's 1.534 of the code_aster validation test SSNP006
     (manual V6.03.006; attributed there to Verruijt).
  3. The strength divisor: with D equal to the minimum factor, the critical circle's
     factor is 1 (the definition of the factor of safety as a strength divisor).
Python 3 standard library and numpy only.
"""
import argparse
import math
import sys

import numpy as np


class Slope:
    """A homogeneous dry slope under a ground polyline.

    Internally the ground rises with x (the slope faces -x, the slip mass moves toward -x);
    a slope that faces +x is mirrored on input and its circles mirrored back on output.
    """

    def __init__(self, ground, gamma, c, phi_deg, divisor=1.0, floor=None):
        pts = np.array(sorted((float(x), float(y)) for x, y in ground))
        if len(pts) < 2 or np.any(np.diff(pts[:, 0]) <= 0):
            raise ValueError("the ground needs two or more points with distinct x")
        self.mirrored = pts[0, 1] > pts[-1, 1]
        if self.mirrored:
            pts = np.array(sorted((-x, y) for x, y in pts))
        self.x, self.y = pts[:, 0], pts[:, 1]
        self.gamma = float(gamma)
        self.c = float(c) / divisor
        self.tanphi = math.tan(math.radians(phi_deg)) / divisor
        self.floor = floor
        # toe: the first vertex where the ground starts to rise; crest: where it stops
        rising = np.nonzero(np.diff(self.y) > 0)[0]
        if len(rising) == 0:
            raise ValueError("flat ground: no slope")
        self.i_toe, self.i_crest = rising[0], rising[-1] + 1
        self.height = self.y[self.i_crest] - self.y[self.i_toe]

    # --- geometry -------------------------------------------------------------------
    def ground_at(self, x):
        return np.interp(x, self.x, self.y)

    def to_user(self, x):
        return -x if self.mirrored else x

    def from_user(self, x):
        return -x if self.mirrored else x

    def toe(self):
        return self.x[self.i_toe], self.y[self.i_toe]

    def crest(self):
        return self.x[self.i_crest], self.y[self.i_crest]

    def slip_interval(self, xc, yc, R):
        """[x_entry, x_exit] where the circle's lower arc runs below the ground, or None."""
        xs = []
        for i in range(len(self.x) - 1):
            x0, y0, x1, y1 = self.x[i], self.y[i], self.x[i + 1], self.y[i + 1]
            dx, dy = x1 - x0, y1 - y0
            fx, fy = x0 - xc, y0 - yc
            a = dx * dx + dy * dy
            b = 2 * (fx * dx + fy * dy)
            cc = fx * fx + fy * fy - R * R
            disc = b * b - 4 * a * cc
            if disc < 0:
                continue
            sq = math.sqrt(disc)
            for t in ((-b - sq) / (2 * a), (-b + sq) / (2 * a)):
                if -1e-12 <= t <= 1 + 1e-12:
                    yi = y0 + t * dy
                    if yi <= yc:                    # on the lower arc
                        xs.append(x0 + t * dx)
        xs = sorted(set(round(v, 12) for v in xs))
        if len(xs) < 2:
            return None
        best = None
        for xa, xb in zip(xs[:-1], xs[1:]):
            xm = 0.5 * (xa + xb)
            if abs(xm - xc) >= R:
                continue
            if self.ground_at(xm) > yc - math.sqrt(R * R - (xm - xc) ** 2):
                if best is None or xb - xa > best[1] - best[0]:
                    best = (xa, xb)
        if best is None:
            return None
        xa, xb = best
        # the slip mass must not reach the ends of the polyline, nor the arc's ends
        if xa <= self.x[0] + 1e-9 or xb >= self.x[-1] - 1e-9:
            return None
        if xa <= xc - R + 1e-9 or xb >= xc + R - 1e-9:
            return None
        return best

    def slices(self, xc, yc, R, n):
        iv = self.slip_interval(xc, yc, R)
        if iv is None:
            return None
        xa, xb = iv
        if self.floor is not None and xa < xc < xb and yc - R < self.floor - 1e-9:
            return None
        edges = np.linspace(xa, xb, n + 1)
        inner = self.x[(self.x > xa) & (self.x < xb)]
        edges = np.unique(np.concatenate([edges, inner]))
        b = np.diff(edges)
        xm = 0.5 * (edges[:-1] + edges[1:])
        ybase = yc - np.sqrt(np.maximum(R * R - (xm - xc) ** 2, 0.0))
        h = self.ground_at(xm) - ybase
        if np.any(h < -1e-9):
            return None
        W = self.gamma * b * np.maximum(h, 0.0)
        sina = (xm - xc) / R
        cosa = np.sqrt(1.0 - sina * sina)
        return b, W, sina, cosa

    # --- factors of safety ------------------------------------------------------------
    def bishop(self, xc, yc, R, n=100, ordinary=False):
        """Bishop's (or, with ordinary=True, Fellenius') factor of one circle, or inf."""
        s = self.slices(xc, yc, R, n)
        if s is None:
            return math.inf
        b, W, sina, cosa = s
        drive = np.sum(W * sina)
        if drive <= 0:
            return math.inf
        if ordinary:
            return float(np.sum(self.c * b / cosa + W * cosa * self.tanphi) / drive)
        F = 1.0
        for _ in range(200):
            m = cosa + sina * self.tanphi / F
            if np.any(m <= 0):
                return math.inf
            Fn = float(np.sum((self.c * b + W * self.tanphi) / m) / drive)
            if abs(Fn - F) < 1e-10 * F:
                return Fn
            F = Fn
        return F

    def search(self, n=100, grid=24, radii=24, refine=6):
        """Minimum Bishop factor over circles: grid of centres x tangent elevations, then
        Nelder-Mead from the best `refine` circles. Returns (F, xc, yc, R) internally."""
        xt, yt = self.toe()
        xcr, ycr = self.crest()
        H = self.height
        low = self.floor if self.floor is not None else yt - H
        cands = []
        for xc in np.linspace(xt - 0.5 * H, xcr + 0.5 * H, grid):
            for yc in np.linspace(yt + 0.25 * H, ycr + 3.0 * H, grid):
                Rs = [yc - yt_ for yt_ in np.linspace(low, ycr - 0.02 * H, radii)]
                Rs.append(math.hypot(xc - xt, yc - yt))          # through the toe
                for R in Rs:
                    if R <= 0:
                        continue
                    F = self.bishop(xc, yc, R, n=max(20, n // 3))
                    if math.isfinite(F):
                        cands.append((F, xc, yc, R))
        if not cands:
            raise RuntimeError("no admissible circle in the search grid")
        cands.sort()
        best = None
        picked = []
        for cand in cands:
            # start points that are not all the same circle
            if all(math.dist(cand[1:], p[1:]) > 0.1 * H for p in picked):
                picked.append(cand)
            if len(picked) == refine:
                break
        for F0, xc, yc, R in picked:
            res = nelder_mead(lambda v: self.bishop(v[0], v[1], v[2], n=n),
                              [xc, yc, R], step=0.1 * H)
            if best is None or res[0] < best[0]:
                best = res
        return best

    def describe(self, xc, yc, R, n=100):
        xa, xb = self.slip_interval(xc, yc, R)
        ends = sorted([(self.to_user(xa), float(self.ground_at(xa))),
                       (self.to_user(xb), float(self.ground_at(xb)))])
        lowest = yc - R if xa < xc < xb else min(self.ground_at(xa), self.ground_at(xb))
        return {
            "bishop": self.bishop(xc, yc, R, n),
            "ordinary": self.bishop(xc, yc, R, n, ordinary=True),
            "centre": (self.to_user(xc), yc),
            "radius": R,
            "ends": ends,
            "lowest": float(lowest),
        }


def nelder_mead(f, x0, step, tol=1e-7, max_iter=2000):
    """Minimise f over R^n from x0 (standard Nelder-Mead); returns (f_min, *x_min)."""
    x0 = np.asarray(x0, float)
    n = len(x0)
    simplex = [x0] + [x0 + step * e for e in np.eye(n)]
    values = [f(p) for p in simplex]
    for _ in range(max_iter):
        order = np.argsort(values)
        simplex = [simplex[i] for i in order]
        values = [values[i] for i in order]
        if math.isfinite(values[-1]) and values[-1] - values[0] < tol * max(1.0, abs(values[0])):
            break
        centroid = np.mean(simplex[:-1], axis=0)
        xr = centroid + (centroid - simplex[-1])
        fr = f(xr)
        if fr < values[0]:
            xe = centroid + 2 * (centroid - simplex[-1])
            fe = f(xe)
            simplex[-1], values[-1] = (xe, fe) if fe < fr else (xr, fr)
        elif fr < values[-2]:
            simplex[-1], values[-1] = xr, fr
        else:
            xk = centroid + 0.5 * (simplex[-1] - centroid)
            fk = f(xk)
            if fk < values[-1]:
                simplex[-1], values[-1] = xk, fk
            else:
                simplex = [simplex[0] + 0.5 * (p - simplex[0]) for p in simplex]
                values = [values[0]] + [f(p) for p in simplex[1:]]
    i = int(np.argmin(values))
    return (values[i], *simplex[i])


# --- the cases -------------------------------------------------------------------------
# This example (README.md): H = 4.5 m, 1:2 slope facing +x, crest at x = 9 m, toe at
# x = 18 m, 2 m of foundation down to the fixed base at y = 0, 9 m (2H) behind the crest
# and in front of the toe, as slope.geo.
EXAMPLE = dict(ground=[(0.0, 6.5), (9.0, 6.5), (18.0, 2.0), (27.0, 2.0)],
               gamma=16.0, c=5.0, phi=20.0)
EXAMPLE_FLOOR = 0.0
EXAMPLE_BISHOP = 1.534          # code_aster V6.03.006 (SSNP006): Verruijt, Bishop simplified
EXAMPLE_SRM = 1.54              # the same document: Plaxis2D, strength reduction

# Fredlund & Krahn (1977), example case 1 (ft, psf, pcf).
FK_GROUND = [(0.0, 60.0), (60.0, 60.0), (140.0, 20.0), (170.0, 20.0)]
FK_CIRCLE = (120.0, 90.0, 80.0)
FK_BISHOP, FK_ORDINARY = 2.080, 1.928


def report(slope, xc, yc, R, n, title):
    d = slope.describe(xc, yc, R, n)
    (x1, y1), (x2, y2) = d["ends"]
    print(title)
    print(f"  Bishop simplified FS = {d['bishop']:.4f}   (ordinary method {d['ordinary']:.4f})")
    print(f"  circle: centre ({d['centre'][0]:.3f}, {d['centre'][1]:.3f}), radius {d['radius']:.3f}")
    print(f"  cuts the ground at ({x1:.3f}, {y1:.3f}) and ({x2:.3f}, {y2:.3f}); "
          f"lowest point {d['lowest']:.3f}")
    return d


def check(n):
    ok = True

    def expect(name, got, want, tol=0.01):
        nonlocal ok
        err = got / want - 1
        good = abs(err) <= tol
        ok &= good
        print(f"  {'ok  ' if good else 'FAIL'} {name}: {got:.4f} against {want:.4f} ({100 * err:+.2f} %)")

    print("1. Fredlund & Krahn (1977), case 1, the given circle:")
    fk = Slope(FK_GROUND, 120.0, 600.0, 20.0)
    xc, yc, R = FK_CIRCLE
    expect("Bishop simplified", fk.bishop(fk.from_user(xc), yc, R, n), FK_BISHOP)
    expect("ordinary method", fk.bishop(fk.from_user(xc), yc, R, n, ordinary=True), FK_ORDINARY)

    print("2. This example (code_aster SSNP006), search with the base y = 0 as floor:")
    s = Slope(EXAMPLE["ground"], EXAMPLE["gamma"], EXAMPLE["c"], EXAMPLE["phi"],
              floor=EXAMPLE_FLOOR)
    F, xc, yc, R = s.search(n=n)
    expect("minimum Bishop FS", F, EXAMPLE_BISHOP)
    d = s.describe(xc, yc, R, n)
    print(f"       critical circle: centre ({d['centre'][0]:.2f}, {d['centre'][1]:.2f}), "
          f"R = {R:.2f}, from ({d['ends'][0][0]:.2f}, {d['ends'][0][1]:.2f}) "
          f"to ({d['ends'][1][0]:.2f}, {d['ends'][1][1]:.2f})")

    print("3. Strength divisor D = FS: the critical circle's factor becomes 1:")
    sd = Slope(EXAMPLE["ground"], EXAMPLE["gamma"], EXAMPLE["c"], EXAMPLE["phi"],
               divisor=F, floor=EXAMPLE_FLOOR)
    expect("FS at c/D, tan(phi)/D", sd.bishop(xc, yc, R, n), 1.0, tol=1e-3)
    print("all checks passed" if ok else "CHECK FAILED")
    return 0 if ok else 1


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--check", action="store_true", help="self-check against published results")
    p.add_argument("--ground", help='ground polyline "x,y x,y ..." (default: this example)')
    p.add_argument("--gamma", type=float, help="unit weight")
    p.add_argument("--c", type=float, help="cohesion")
    p.add_argument("--phi", type=float, help="friction angle, degrees")
    p.add_argument("--divisor", type=float, default=1.0,
                   help="divide c and tan(phi) by this before the analysis")
    p.add_argument("--floor", type=float,
                   help="no circle below this elevation (default: the example's base, y = 0, "
                        "for the example; none for --ground)")
    p.add_argument("--circle", help="evaluate one circle XC,YC,R instead of searching")
    p.add_argument("--slices", type=int, default=100, help="slices per circle (default 100)")
    p.add_argument("--grid", type=int, default=24, help="centres per side of the search grid")
    a = p.parse_args(argv)
    if a.check:
        return check(a.slices)
    if a.ground:
        ground = [tuple(map(float, pt.split(","))) for pt in a.ground.split()]
        floor = a.floor
    else:
        ground = EXAMPLE["ground"]
        floor = EXAMPLE_FLOOR if a.floor is None else a.floor
    gamma = a.gamma if a.gamma is not None else EXAMPLE["gamma"]
    c = a.c if a.c is not None else EXAMPLE["c"]
    phi = a.phi if a.phi is not None else EXAMPLE["phi"]
    s = Slope(ground, gamma, c, phi, divisor=a.divisor, floor=floor)
    print(f"ground {ground}, gamma {gamma:g}, c {c:g}, phi {phi:g} deg, "
          f"strength divisor {a.divisor:g}, floor {floor}")
    if a.circle:
        xc, yc, R = map(float, a.circle.split(","))
        if not math.isfinite(s.bishop(s.from_user(xc), yc, R, a.slices)):
            print("that circle is not admissible (see the module docstring)")
            return 1
        report(s, s.from_user(xc), yc, R, a.slices, "the given circle:")
    else:
        F, xc, yc, R = s.search(n=a.slices, grid=a.grid)
        report(s, xc, yc, R, a.slices, "critical circle (minimum over the search):")
    return 0


if __name__ == "__main__":
    sys.exit(main())
