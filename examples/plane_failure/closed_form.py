#!/usr/bin/env python3
"""Hoek & Bray's plane failure: the closed-form factor of safety of every scenario here.

Hoek & Bray (1981), Wyllie & Mah (2004, ch. 6); README.md. Per unit width,
a vertical tension crack of depth z in the upper surface behind the crest, water standing z_w
deep in it and falling linearly along the plane to zero where the plane daylights:

    A = (H - z) / sin(psi_p)                 plane length (m)
    U = g_w z_w A / 2                        uplift on the plane (kN/m)
    V = g_w z_w^2 / 2                        push of the crack's water (kN/m)
    W = g_r H^2 [(1 - (z/H)^2) cot(psi_p) - cot(psi_f)] / 2        weight (kN/m)
    FS = [c A + (W (cos psi_p - kh sin psi_p) - U - V sin psi_p) tan phi]
         / [W (sin psi_p + kh cos psi_p) + V cos psi_p]

kh: a pseudo-static horizontal force kh W toward the face. Units: m, deg, kPa, kN/m^3.

    python3 closed_form.py              the table of every shipped scenario
    python3 closed_form.py --check      asserts README.md's published numbers, the reporter's
                                        (c = 25 kPa, phi = 35 deg) and that each scenario file
                                        (and its .geo) holds the parameters of its row
    python3 closed_form.py --H 20 --psi-f 60 --psi-p 35 --z 8 --zw 4 --c 25 --phi 35 --gamma-r 25.9965
                                        one case
"""
import argparse
import json
import math
import os
import re
import sys

G = 9.81                 # m/s^2, as dsdem
HERE = os.path.dirname(os.path.abspath(__file__))


def plane_failure(H, psi_f, psi_p, z, z_w, c, phi, gamma_r, gamma_w=G, kh=0.0):
    """Hoek & Bray's plane failure with a vertical tension crack: a dict of A, W, U, V, FS."""
    d = math.pi / 180.0
    if not 0.0 < psi_p < psi_f <= 90.0:
        raise ValueError(f"the plane must be flatter than the face: psi_p = {psi_p}, psi_f = {psi_f}")
    if not 0.0 <= z < H:
        raise ValueError(f"the crack depth z = {z} must lie in [0, H = {H})")
    if not 0.0 <= z_w <= z:
        raise ValueError(f"the water depth in the crack z_w = {z_w} must lie in [0, z = {z}]")
    behind_crest = (H - z) / math.tan(psi_p * d) - H / math.tan(psi_f * d)
    if behind_crest < -1e-12:
        raise ValueError(f"the crack must be in the upper surface: it is {-behind_crest:.3f} m inside the face "
                         "(these formulas do not hold for a crack in the face)")
    A = (H - z) / math.sin(psi_p * d)
    U = gamma_w * z_w * A / 2.0
    V = gamma_w * z_w ** 2 / 2.0
    W = gamma_r * H ** 2 * ((1.0 - (z / H) ** 2) / math.tan(psi_p * d) - 1.0 / math.tan(psi_f * d)) / 2.0
    s, co, t = math.sin(psi_p * d), math.cos(psi_p * d), math.tan(phi * d)
    resisting = c * A + (W * (co - kh * s) - U - V * s) * t
    driving = W * (s + kh * co) + V * co
    return {"A": A, "W": W, "U": U, "V": V, "FS": resisting / driving, "behind_crest": behind_crest}


# The shipped scenarios. "readme": the first cell of the scenario's row in README.md.
# "expect": the published value (README.md, or the reporter's for c = 25 kPa / phi = 35 deg)
# and the number of decimals it was published with.
GEOMETRY = {"H": 20.0, "psi_f": 60.0, "psi_p": 35.0}
EXISTING = {"c": 30.0, "phi": 30.0, "rho": 2500.0}      # examples/plane_failure (c kPa, phi deg, rho kg/m^3)
REPORTED = {"c": 25.0, "phi": 35.0, "rho": 2650.0}      # the reporters' case
SCENARIOS = [
    {"file": "dry.yaml", "readme": "`dry.yaml`", "z": 0, "z_w": 0, **EXISTING, "expect": (1.2616, 4)},
    {"file": "crack_dry.yaml", "readme": "`crack_dry.yaml`", "z": 8, "z_w": 0, **EXISTING, "expect": (1.1830, 4)},
    {"file": "crack_half_water.yaml", "readme": "`crack_half_water.yaml`", "z": 8, "z_w": 4, **EXISTING},
    {"file": "crack_water.yaml", "readme": "`crack_water.yaml`", "z": 8, "z_w": 8, **EXISTING, "expect": (0.7437, 4)},
    {"file": "dry.yaml", "readme": "`dry.yaml --kh 0.1` (pseudo-static)", "z": 0, "z_w": 0, "kh": 0.1,
     **EXISTING, "expect": (1.0534, 4)},
    {"file": "c25_phi35/crack_dry.yaml", "readme": "`c25_phi35/crack_dry.yaml`", "z": 8, "z_w": 0, **REPORTED,
     "expect": (1.282, 3)},
    {"file": "c25_phi35/crack_half.yaml", "readme": "`c25_phi35/crack_half.yaml`", "z": 8, "z_w": 4, **REPORTED,
     "expect": (1.073, 3)},
    {"file": "c25_phi35/crack_full.yaml", "readme": "`c25_phi35/crack_full.yaml`", "z": 8, "z_w": 8, **REPORTED,
     "expect": (0.794, 3)},
]


def evaluate(sc):
    return plane_failure(GEOMETRY["H"], GEOMETRY["psi_f"], GEOMETRY["psi_p"], sc["z"], sc["z_w"], sc["c"], sc["phi"],
                         sc["rho"] * G / 1000.0, G, sc.get("kh", 0.0))


def table():
    head = (f"{'scenario':<38} {'c kPa':>5} {'phi':>4} {'rho':>5} {'z':>3} {'z_w':>4} {'kh':>4} "
            f"{'W MN/m':>8} {'A m':>7} {'U MN/m':>7} {'V MN/m':>7} {'FS':>7}")
    lines = [head, "-" * len(head)]
    for sc in SCENARIOS:
        r = evaluate(sc)
        name = sc["readme"].replace("`", "")
        lines.append(f"{name:<38} {sc['c']:>5g} {sc['phi']:>4g} {sc['rho']:>5g} {sc['z']:>3g} {sc['z_w']:>4g} "
                     f"{sc.get('kh', 0.0):>4g} {r['W'] / 1e3:>8.4f} {r['A']:>7.3f} {r['U'] / 1e3:>7.4f} "
                     f"{r['V'] / 1e3:>7.4f} {r['FS']:>7.4f}")
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# --check: the published numbers and the files


class Failures:
    def __init__(self):
        self.items = []
        self.count = 0

    def expect(self, ok, what):
        self.count += 1
        if not ok:
            self.items.append(what)


def close(value, published, decimals):
    """value rounds to the published number (to its decimals)."""
    return abs(value - published) <= 0.5 * 10.0 ** -decimals + 1e-12


def decimals_of(text):
    return len(text.split(".")[1]) if "." in text else 0


def readme_rows(path):
    """The rows of README.md's scenario tables: {first cell: [{header: cell}, ...]} (a scenario may
    have a row in more than one table)."""
    rows = {}
    header = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line.startswith("|"):
                header = None
                continue
            cells = [x.strip() for x in line.strip("|").split("|")]
            if cells and cells[0] == "scenario":
                header = cells
            elif header and not set(cells[0]) <= set("-: "):
                rows.setdefault(cells[0], []).append(dict(zip(header, cells)))
    return rows


def parse_geo(path):
    """The plane-failure .geo's parameters: H, h0, xt, hd, z (0 without a crack), psi_f, psi_p."""
    text = open(path, encoding="utf-8").read()
    text = re.sub(r"//[^\n]*", "", text)
    g = {k: float(v) for k, v in re.findall(r"\b(H|h0|xt|hd|z)\s*=\s*([0-9.]+)\s*;", text)}
    g.setdefault("z", 0.0)
    cf = re.search(r"cf\s*=\s*1\s*/\s*Tan\(\s*([0-9.]+)\s*\*\s*Pi\s*/\s*180\s*\)", text)
    cp = re.search(r"cp\s*=\s*1\s*/\s*Tan\(\s*([0-9.]+)\s*\*\s*Pi\s*/\s*180\s*\)", text)
    g["psi_f"], g["psi_p"] = float(cf.group(1)), float(cp.group(1))
    return g


def key_points(g):
    """Daylight point, crest, crack top and foot (x, y) of the .geo (slope_crack.geo's Points 9, 5, 6, 8)."""
    d = math.pi / 180.0
    cf, cp = 1.0 / math.tan(g["psi_f"] * d), 1.0 / math.tan(g["psi_p"] * d)
    top = g["h0"] + g["hd"] + g["H"]
    daylight = (g["xt"] - g["hd"] * cf, g["h0"] + g["hd"])
    crest = (g["xt"] - (g["hd"] + g["H"]) * cf, top)
    crack_x = daylight[0] - (g["H"] - g["z"]) * cp
    return daylight, crest, (crack_x, top), (crack_x, top - g["z"])


def line_at(line, x):
    for (x0, y0), (x1, y1) in zip(line, line[1:]):
        if x0 <= x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    raise ValueError(f"x = {x} outside the line")


def inside(poly, p):
    n, ok = len(poly), False
    for i in range(n):
        (x0, y0), (x1, y1) = poly[i], poly[(i + 1) % n]
        if (y0 > p[1]) != (y1 > p[1]) and p[0] < x0 + (p[1] - y0) * (x1 - x0) / (y1 - y0):
            ok = not ok
    return ok


def number(pattern, text, what, fails, path):
    m = re.search(pattern, text)
    fails.expect(m is not None, f"{path}: no {what}")
    return float(m.group(1)) if m else math.nan


def check_file(sc, fails):
    """The scenario file holds its row's parameters; its water is Hoek & Bray's."""
    path = os.path.join(HERE, sc["file"])
    name = sc["file"]
    text = open(path, encoding="utf-8").read()
    body = re.sub(r"#[^\n]*", "", text)          # no comments
    geo = re.search(r"^\s*file:\s*(\S+)", body, re.M).group(1)
    g = parse_geo(os.path.join(os.path.dirname(path), geo))
    for k in ("H", "psi_f", "psi_p"):
        fails.expect(g[k] == GEOMETRY[k], f"{name}: {geo} has {k} = {g[k]}, the table {GEOMETRY[k]}")
    fails.expect(g["z"] == sc["z"], f"{name}: {geo} has z = {g['z']}, the table {sc['z']}")
    rho = number(r"rock:\s*\{[^}]*\brho:\s*([0-9.eE+-]+)", body, "rock rho", fails, name)
    fails.expect(rho == sc["rho"], f"{name}: rho = {rho}, the table {sc['rho']}")
    plane = re.search(r"^\s*plane:\s*\{([^}]*)\}", body, re.M)
    fails.expect(plane is not None, f"{name}: no joints.curves.plane")
    if plane:
        c = number(r"\bc:\s*([0-9.eE+-]+)", plane.group(1), "plane c", fails, name)
        phi = number(r"\bphi:\s*([0-9.eE+-]+)", plane.group(1), "plane phi", fails, name)
        ft = number(r"\bft:\s*([0-9.eE+-]+)", plane.group(1), "plane ft", fails, name)
        gii = number(r"\bGII:\s*([0-9.eE+-]+)", plane.group(1), "plane GII", fails, name)
        fails.expect(c == sc["c"] * 1e3, f"{name}: plane c = {c} Pa, the table {sc['c']} kPa")
        fails.expect(phi == sc["phi"], f"{name}: plane phi = {phi}, the table {sc['phi']}")
        fails.expect(ft <= 1.0, f"{name}: plane ft = {ft} Pa: not 'no tension'")
        fails.expect(abs(2 * gii / c - 0.1) < 1e-9, f"{name}: softening length 2 GII/c = {2 * gii / c} m, not 0.1")
    mu = number(r"(?m)^\s*friction:\s*([0-9.eE+-]+)", body, "contact friction", fails, name)
    fails.expect(abs(mu - math.tan(sc["phi"] * math.pi / 180)) < 1e-5,
                 f"{name}: contact friction {mu} is not tan({sc['phi']} deg)")
    daylight, crest, crack_top, crack_foot = key_points(g)
    # the water: none for z_w = 0; else one line, level z_w above the crack's foot behind the
    # crack, straight to the daylight point, then the face and the ground below the toe
    water = re.search(r"^water:", body, re.M)
    m = re.search(r"^\s*line:\s*(\[\[.*?\]\])\s*$", body, re.M)
    if sc["z_w"] == 0:
        fails.expect(water is None, f"{name}: a dry crack with a water section")
    else:
        fails.expect(water is not None and m is not None, f"{name}: no water.line")
        fails.expect(re.search(r"^\s*pore_pressure:\s*discontinuities\s*$", body, re.M) is not None,
                     f"{name}: water without pore_pressure: discontinuities")
        dens = re.search(r"^\s*density:\s*([0-9.eE+-]+)", body, re.M)
        fails.expect(dens is None or float(dens.group(1)) == 1000.0, f"{name}: water density is not 1000")
        if m:
            line = [tuple(p) for p in json.loads(m.group(1))]
            level = crack_foot[1] + sc["z_w"]
            tol = 1e-3                                     # m: the file's rounding
            fails.expect(all(abs(y - level) < 1e-12 for x, y in line if x < crack_foot[0] - tol),
                         f"{name}: the line behind the crack is not level at {level}")
            fails.expect(abs(line_at(line, crack_foot[0]) - level) < tol,
                         f"{name}: the line at the crack (x = {crack_foot[0]:.6f}) is "
                         f"{line_at(line, crack_foot[0]):.6f}, not the level {level}")
            fails.expect(abs(line_at(line, daylight[0]) - daylight[1]) < tol,
                         f"{name}: the line does not pass through the daylight point {daylight}")
            fails.expect(any(abs(x - crack_foot[0]) < tol and abs(y - level) < 1e-12 for x, y in line) and
                         any(abs(x - daylight[0]) < tol and abs(y - daylight[1]) < 1e-12 for x, y in line),
                         f"{name}: the line has no vertex at (crack, level) and at the daylight point")
            # straight between them: the head on the plane is linear, from z_w to 0
            between = [p for p in line if crack_foot[0] + tol < p[0] < daylight[0] - tol]
            fails.expect(not between, f"{name}: the line has vertices between the crack and daylight: {between}")
            fails.expect(abs(line[-1][1] - (g["h0"])) < 1e-12 and abs(line_at(line, g["xt"]) - g["h0"]) < tol,
                         f"{name}: the line does not follow the face and the ground below the daylight point")
            fails.expect(line[0][0] <= 0.0 and line[-1][0] >= g["xt"] + 20.0, f"{name}: the line does not span the model")
    # stability: bounds around the closed form, a monitor inside the block
    fs = evaluate(sc)["FS"]
    b = re.search(r"^\s*bounds:\s*\[\s*([0-9.]+)\s*,\s*([0-9.]+)\s*\]", body, re.M)
    fails.expect(b is not None, f"{name}: no stability.bounds")
    if b:
        lo, hi = float(b.group(1)), float(b.group(2))
        fails.expect(lo < 0.85 * fs and hi > 1.15 * fs,
                     f"{name}: stability.bounds [{lo}, {hi}] do not bracket FS = {fs:.4f} by 15 %")
    mon = re.search(r"monitor:\s*\n\s*-\s*\{[^}]*\bat:\s*\[\s*([0-9.]+)\s*,\s*([0-9.]+)\s*\]", body)
    fails.expect(mon is not None, f"{name}: no stability.monitor")
    if mon:
        block = [daylight, crest, crack_top, crack_foot] if g["z"] > 0 else [daylight, crest, crack_top]
        at = (float(mon.group(1)), float(mon.group(2)))
        fails.expect(inside(block, at), f"{name}: the monitor {at} is not inside the block {block}")


def check():
    fails = Failures()
    rows = readme_rows(os.path.join(HERE, "README.md"))
    for sc in SCENARIOS:
        r = evaluate(sc)
        tag = sc["readme"]
        if "expect" in sc:
            value, dec = sc["expect"]
            fails.expect(close(r["FS"], value, dec), f"{tag}: FS = {r['FS']:.5f}, published {value}")
        fails.expect(tag in rows, f"{tag}: no row in README.md")
        for row in rows.get(tag, []):
            for head, key, scale in (("W (MN/m)", "W", 1e-3), ("A (m)", "A", 1.0), ("U (MN/m)", "U", 1e-3),
                                     ("V (MN/m)", "V", 1e-3)):
                if head in row:
                    cell = row[head]
                    fails.expect(close(r[key] * scale, float(cell), decimals_of(cell)),
                                 f"{tag}: README {head} {cell}, computed {r[key] * scale:.5f}")
            fs_cell = next((v for k, v in row.items() if k.startswith("closed-form FS")), "")
            m = re.fullmatch(r"\*\*([0-9.]+)\*\*", fs_cell)
            fails.expect(m is not None, f"{tag}: README's closed-form FS cell '{fs_cell}' is not **x.xxxx**")
            if m:
                fails.expect(close(r["FS"], float(m.group(1)), decimals_of(m.group(1))),
                             f"{tag}: README FS {m.group(1)}, computed {r['FS']:.5f}")
        check_file(sc, fails)
    # The reporter's 'dry 1.282' is the dry 8 m crack at rho = 2650; with no crack it is 1.3436, and
    # 1.2987 is the dry crack at the example's rho = 2500.
    rep = dict(REPORTED, z=8, z_w=0)
    fails.expect(close(evaluate(dict(rep, z=0))["FS"], 1.3436, 4), "no crack, c25/phi35, rho 2650: not 1.3436")
    fails.expect(close(evaluate(dict(rep, rho=2500))["FS"], 1.2987, 4), "dry crack, c25/phi35, rho 2500: not 1.2987")
    # the closed form against the block's own area (shoelace) times the unit weight
    for z in (0.0, 8.0):
        g = dict(parse_geo(os.path.join(HERE, "slope_crack.geo" if z else "slope.geo")))
        daylight, crest, top, foot = key_points(g)
        poly = [daylight, crest, top, foot] if z else [daylight, crest, top]
        area = abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(poly, poly[1:] + poly[:1]))) / 2
        w = plane_failure(20, 60, 35, z, 0, 0, 30, 1.0)["W"]
        fails.expect(abs(area - w) < 1e-9, f"z = {z}: the .geo block's area {area} is not W / g_r = {w}")
    for f in fails.items:
        print("FAIL:", f)
    print(f"{fails.count - len(fails.items)} of {fails.count} checks passed")
    return 0 if not fails.items else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="assert README.md's numbers and the scenario files")
    ap.add_argument("--H", type=float, help="height of the block above the daylight point (m)")
    ap.add_argument("--psi-f", type=float, default=60.0, help="face angle (deg)")
    ap.add_argument("--psi-p", type=float, default=35.0, help="plane angle (deg)")
    ap.add_argument("--z", type=float, default=0.0, help="tension crack depth (m)")
    ap.add_argument("--zw", type=float, default=0.0, help="water depth in the crack (m)")
    ap.add_argument("--c", type=float, default=30.0, help="cohesion on the plane (kPa)")
    ap.add_argument("--phi", type=float, default=30.0, help="friction angle on the plane (deg)")
    ap.add_argument("--gamma-r", type=float, default=2500 * G / 1000, help="rock unit weight (kN/m^3)")
    ap.add_argument("--gamma-w", type=float, default=G, help="water unit weight (kN/m^3)")
    ap.add_argument("--kh", type=float, default=0.0, help="pseudo-static horizontal coefficient toward the face")
    a = ap.parse_args()
    if a.check:
        return check()
    if a.H is not None:
        r = plane_failure(a.H, a.psi_f, a.psi_p, a.z, a.zw, a.c, a.phi, a.gamma_r, a.gamma_w, a.kh)
        print(f"W = {r['W']:.4f} kN/m  A = {r['A']:.4f} m  U = {r['U']:.4f} kN/m  V = {r['V']:.4f} kN/m  "
              f"FS = {r['FS']:.4f}")
        return 0
    print(table())
    return 0


if __name__ == "__main__":
    sys.exit(main())
