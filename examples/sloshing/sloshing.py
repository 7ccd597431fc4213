#!/usr/bin/env python3
"""The first sloshing mode of the tank (examples/sloshing) from a run's history.csv.

    sloshing.py OUT [--length 1] [--depth 0.5] [--after 1.2] [--plot sloshing.png]

The free surface at the gauges g00..g19 (evenly spaced across the tank, at x = (i + 1/2) L / 20)
is projected on the first mode's shape cos(pi x / L): a1(t) = (2 / n) sum_i eta_i cos(pi x_i / L)
(the midpoint rule of (2 / L) int eta cos(k x) dx), which leaves out the symmetric modes and
the tank's mean level. After the shake (t > --after) a1 oscillates freely: its period is the
mean spacing of its zero crossings (two per period), its decay the fitted slope of the log of
its extremes. Both against linear theory: T1 = 2 pi / sqrt(g k tanh(k h)), k = pi / L.
"""
import argparse
import csv
import math
import sys
from pathlib import Path


def read_history(path: Path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    names = rows[0]
    return names, [[float(v) for v in r] for r in rows[1:]]


def fit_line(x, y):
    n = len(x)
    mx, my = sum(x) / n, sum(y) / n
    sxx = sum((a - mx) ** 2 for a in x)
    sxy = sum((a - mx) * (b - my) for a, b in zip(x, y))
    slope = sxy / sxx
    return slope, my - slope * mx


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", type=Path, help="the run's output folder (history.csv)")
    ap.add_argument("--length", type=float, default=1.0, help="the tank's inside length L (m)")
    ap.add_argument("--depth", type=float, default=0.5, help="the still water depth h (m)")
    ap.add_argument("--after", type=float, default=1.2, help="the free sloshing from this time on (s)")
    ap.add_argument("--plot", type=Path, help="write a1(t) and its envelope to this PNG")
    a = ap.parse_args()

    g = 9.81
    k = math.pi / a.length
    T_exact = 2.0 * math.pi / math.sqrt(g * k * math.tanh(k * a.depth))

    names, rows = read_history(a.out / "history.csv")
    gauges = sorted(n for n in names if n.startswith("g") and n.endswith("_eta_m"))
    if not gauges:
        print("history.csv has no gauge columns g..._eta_m", file=sys.stderr)
        return 2
    n = len(gauges)
    cols = [names.index(c) for c in gauges]
    xs = [(i + 0.5) * a.length / n for i in range(n)]
    t_col = names.index("time_s")
    t = [r[t_col] for r in rows]
    a1 = [2.0 / n * sum(r[c] * math.cos(k * x) for c, x in zip(cols, xs)) for r in rows]

    free = [(ti, ai) for ti, ai in zip(t, a1) if ti >= a.after and math.isfinite(ai)]
    # Zero crossings, linearly interpolated.
    cross = []
    for (t0, y0), (t1, y1) in zip(free, free[1:]):
        if y0 == 0.0 or (y0 < 0.0) != (y1 < 0.0):
            cross.append(t0 + (t1 - t0) * y0 / (y0 - y1) if y0 != y1 else t0)
    # Extremes between successive crossings, refined by a parabola through the sample and its neighbours.
    ext = []
    for c0, c1 in zip(cross, cross[1:]):
        seg = [i for i, (ti, _) in enumerate(free) if c0 < ti < c1]
        if len(seg) < 3:
            continue
        i = max(seg, key=lambda j: abs(free[j][1]))
        if i == 0 or i + 1 >= len(free):
            continue
        (ta, ya), (tb, yb), (tc, yc) = free[i - 1], free[i], free[i + 1]
        den = ya - 2 * yb + yc
        s = 0.5 * (ya - yc) / den if den != 0 else 0.0
        ext.append((tb + s * (tc - tb), abs(yb - 0.25 * (ya - yc) * s)))
    if len(cross) < 4 or len(ext) < 3:
        print(f"too few crossings ({len(cross)}) or extremes ({len(ext)}) after t = {a.after} s", file=sys.stderr)
        return 1
    half, _ = fit_line(list(range(len(cross))), cross)
    T = 2.0 * half
    slope, icpt = fit_line([e[0] for e in ext], [math.log(e[1]) for e in ext])
    decay = 1.0 - math.exp(slope * T)
    print(f"gauges {n}, free sloshing from t = {a.after} s: {len(cross)} zero crossings, {len(ext)} extremes")
    print(f"first mode period: {T:.5f} s, closed form {T_exact:.5f} s, ratio {T / T_exact:.5f} "
          f"({100.0 * (T / T_exact - 1.0):+.2f} %)")
    print(f"amplitude a1: {ext[0][1] * 1000:.3f} mm at t = {ext[0][0]:.3f} s, {ext[-1][1] * 1000:.3f} mm at "
          f"t = {ext[-1][0]:.3f} s")
    print(f"decay per period: {100.0 * decay:.3f} % (log-linear fit over {len(ext)} half-period extremes; "
          f"damping ratio {-slope * T / (2.0 * math.pi):.5f})")
    # Each period's own decay: successive extremes of the same sign, two apart.
    each = [1.0 - ext[i + 2][1] / ext[i][1] for i in range(len(ext) - 2)]
    print("decay per period, extreme by extreme (%): " + " ".join(f"{100.0 * d:.2f}" for d in each))
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(9, 4), layout="constrained")
        ax.plot(t, [1000 * v for v in a1], lw=1.0, label="a1(t): the free surface on cos(pi x / L)")
        te = [e[0] for e in ext]
        ax.plot(te, [1000 * math.exp(icpt + slope * x) for x in te], "k--", lw=1.0,
                label=f"envelope: {100.0 * decay:.2f} % per period")
        ax.plot(te, [-1000 * math.exp(icpt + slope * x) for x in te], "k--", lw=1.0)
        ax.axvline(a.after, color="0.5", ls=":", lw=1.0, label="the shake ends")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("first-mode amplitude a1 (mm)")
        ax.set_title(f"Sloshing: T1 = {T:.4f} s against {T_exact:.4f} s (linear theory)")
        ax.legend(loc="upper right")
        fig.savefig(a.plot, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
