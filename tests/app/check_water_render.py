#!/usr/bin/env python3
"""Checks that a render of a run with moving water shows the water where its particles are.

    check_water_render.py OUT FRAME WITH_WATER.png WITHOUT_WATER.png

FRAME is a field frame number. The water frame of that moment is found independently of
the renderer: the entry of OUT/water.pvd whose time equals the field frame's time in
OUT/fields.pvd. Each particle inside the view is mapped to its pixel with the PNG's
"dsdem:view" text chunk (axes box in pixels, x and y limits). Passes (exit 0) when the
PNG says it drew the water of that moment ("dsdem:water_time"), at least 90% of the
particles sit on a blue pixel of WITH_WATER and at most 5% on a blue pixel of
WITHOUT_WATER (rendered with --water none: blue comes from the water alone). Prints the
fractions; exit 1 with the reason otherwise.
"""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402


def pvd(path):
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), path.parent / d.get("file")) for d in root.iter("DataSet")]


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def blue_fraction(png, px, py):
    img = mpimg.imread(png)[..., :3] * 255.0
    r, g, b = (img[py, px, k] for k in range(3))
    return float(np.mean((b > r + 40) & (b > g)))


def main():
    out, frame, with_water, without = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3], sys.argv[4]
    fields = pvd(out / "fields.pvd")
    t_field = next(t for t, f in fields if f.name == f"fields_{frame:06d}.vtu")
    matches = [f for t, f in pvd(out / "water.pvd") if abs(t - t_field) <= 1e-9 * max(1.0, abs(t_field))]
    if len(matches) != 1:
        fail(f"{len(matches)} water frames at t = {t_field}")
    text = Image.open(with_water).text
    drawn = text.get("dsdem:water_time", "")
    if not drawn or abs(float(drawn) - t_field) > 1e-9 * max(1.0, abs(t_field)):
        fail(f"the render drew the water of t = '{drawn}', the field frame is at t = {t_field}")
    v = text["dsdem:view"].split()
    ax0, ay0, ax1, ay1 = (float(s) for s in v[1:5])
    x0, x1, y0, y1 = float(v[6]), float(v[7]), float(v[9]), float(v[10])
    xy = np.asarray(meshio.read(str(matches[0])).points)[:, :2]
    inside = (xy[:, 0] > x0) & (xy[:, 0] < x1) & (xy[:, 1] > y0) & (xy[:, 1] < y1)
    if inside.sum() < 50:
        fail(f"only {inside.sum()} particles in the view")
    px = np.round(ax0 + (xy[inside, 0] - x0) / (x1 - x0) * (ax1 - ax0)).astype(int)
    py = np.round(ay1 - (xy[inside, 1] - y0) / (y1 - y0) * (ay1 - ay0)).astype(int)  # rows from the top
    with_frac, without_frac = blue_fraction(with_water, px, py), blue_fraction(without, px, py)
    print(f"particles {inside.sum()}: on blue pixels {with_frac:.3f} with water, {without_frac:.3f} without")
    if with_frac < 0.9:
        fail(f"only {with_frac:.3f} of the particles are on blue pixels")
    if without_frac > 0.05:
        fail(f"{without_frac:.3f} of the particles are on blue pixels without the water")
    print("OK")


if __name__ == "__main__":
    main()
