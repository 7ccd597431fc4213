#!/usr/bin/env python3
"""dsdem render: PNG snapshots of the field frames of a run (and an mp4 movie).

    render_fields.py OUT [--field velocity|displacement|material|stress|damage|ARRAY]
                         [--frames all|last|first|N,M,A-B] [--movie] [--fps 10]
                         [--bbox xmin,xmax,ymin,ymax] [--clim lo,hi] [--width 1280]
                         [--water speed|pressure|none] [--water-clim lo,hi] [--no-cracks] [--no-gauges] [--quiet]
                         [--section x|y|z[=COORDINATE]]

A 3D run (summary.json "dimension": 3, or tetrahedra in the frames) is drawn by
render_fields3d.py instead, with VTK: per frame the model in perspective
(<field>_NNNNNN.png) and a section through it (<field>_section_NNNNNN.png), with the same
fields, frame selection, colour limits, movie and errors.

Reads OUT/fields.pvd (OUT/fields/fields_NNNNNN.vtu, triangles at the deformed
configuration) and, when present, OUT/cracks.pvd (joint segments of the same frame:
broken joints drawn dark, damaged ones coloured by damage) and OUT/water.pvd (the moving
water's particles at the same time, drawn over the rock as discs of the particle spacing
in a blue scale of their own, by speed or pressure; the rock's colour map then has no
blue). Writes
OUT/render/<field>_NNNNNN.png and, with --movie, OUT/render/<field>.mp4. Each PNG carries
its view in the text chunk "dsdem:view" (axes box in pixels from the top left, x and y
limits in m) and the time of the water drawn in "dsdem:water_time".

Colour limits and the view box are fixed across frames (taken from every frame of the
series) so that a movie does not flicker or jump.

Fields:
  velocity      |v| (point data, averaged per triangle), m/s
  displacement  |u|, m
  stress        von Mises stress, Pa
  material      material_id, categorical (names from the scenario when it can be found)
  damage        triangle damage if the fields carry one, otherwise the mesh in grey
                with the joints coloured by damage
  ARRAY         any array of the VTU by name, e.g. max_principal_stress_Pa, zone,
                group_id, or a component: stress_Pa:xx, strain:1
"""

from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dsdem_plotlib as lib  # noqa: E402
import dsdem_water as wat  # noqa: E402
import matplotlib  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap, Normalize  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

try:
    import meshio
except ImportError:  # pragma: no cover
    lib.fail("the Python package meshio is required (Debian: apt install python3-meshio)", 1)

FIELD_ALIASES = lib.FIELD_ALIASES
PRETTY = {
    "velocity_m_per_s": "Velocity magnitude",
    "displacement_m": "Displacement magnitude",
    "acceleration_m_per_s2": "Acceleration magnitude",
    "von_mises_stress_Pa": "Von Mises stress",
    "max_principal_stress_Pa": "Max in-plane principal stress",
    "min_principal_stress_Pa": "Min in-plane principal stress",
    "material_id": "Material",
    "group_id": "Physical group",
    "zone": "Zone",
}
ZONE_NAMES = {0: "A (discrete)", 1: "B (bedrock)", 2: "C (contact bedrock)"}
COMPONENTS = {"x": 0, "y": 1, "z": 2, "xx": 0, "yy": 1, "xy": 2, "gamma_xy": 2}


# ------------------------------------------------------------------------------------
# Field resolution
# ------------------------------------------------------------------------------------


@dataclass
class FieldSpec:
    key: str            # as the user typed it (file names)
    array: str | None   # VTU array name; None: no triangle colouring (grey mesh)
    where: str          # "point" | "cell" | "none"
    component: int | None
    categorical: bool
    label: str
    unit: str
    signed: bool = False


def _arrays(mesh) -> tuple[dict, dict]:
    point = dict(mesh.point_data)
    cell = {}
    for name, blocks in mesh.cell_data.items():
        # Only the triangle block(s) count.
        parts = [b for b, cb in zip(blocks, mesh.cells) if cb.type == "triangle"]
        if parts:
            cell[name] = np.concatenate(parts) if len(parts) > 1 else parts[0]
    return point, cell


def resolve_field(key: str, mesh) -> FieldSpec:
    point, cell = _arrays(mesh)
    name = FIELD_ALIASES.get(key, key)
    comp = None
    if ":" in name:
        name, c = name.split(":", 1)
        if c in COMPONENTS:
            comp = COMPONENTS[c]
        elif c.isdigit():
            comp = int(c)
        else:
            raise lib.InputError(f"--field {key}: unknown component '{c}' (use x, y, xx, yy, xy or an index)")
    if key == "damage":
        for n in list(cell) + list(point):
            if n == "damage" or n.startswith("damage_"):
                name = n
                break
        else:
            return FieldSpec(key, None, "none", None, False, "Joint damage", "")
    where = "point" if name in point else "cell" if name in cell else None
    if where is None:
        avail = sorted(set(point) | set(cell))
        raise lib.InputError(
            f"--field {key}: no array '{name}' in the field frames; use velocity, displacement, material, "
            f"stress, damage or one of: {', '.join(avail)}"
        )
    arr = (point if where == "point" else cell)[name]
    q, unit = lib.split_unit(name)
    categorical = np.issubdtype(arr.dtype, np.integer) and comp is None and arr.ndim == 1
    label = PRETTY.get(name) or lib.humanize(q).capitalize()
    if arr.ndim == 2 and arr.shape[1] > 1:
        if comp is not None:
            if comp >= arr.shape[1]:
                raise lib.InputError(f"--field {key}: '{name}' has only {arr.shape[1]} components")
            label = f"{lib.humanize(q).capitalize()} {['xx', 'yy', 'xy'][comp] if name.startswith(('stress', 'strain')) and comp < 3 else comp}"
        elif where == "cell" and not name.startswith(("velocity", "displacement", "acceleration")):
            raise lib.InputError(
                f"--field {key}: '{name}' has {arr.shape[1]} components; pick one, e.g. --field {name}:0"
            )
        elif name not in PRETTY:
            label = f"{lib.humanize(q).capitalize()} magnitude"
    signed = comp is not None or "principal" in name
    return FieldSpec(key, name, where, comp, categorical, label, unit, signed)


def field_values(spec: FieldSpec, mesh, tri: np.ndarray) -> np.ndarray | None:
    """One value per triangle."""
    if spec.array is None:
        return None
    point, cell = _arrays(mesh)
    arr = (point if spec.where == "point" else cell).get(spec.array)
    if arr is None:
        return None
    arr = np.asarray(arr)
    if arr.ndim == 2 and arr.shape[1] > 1:
        if spec.component is not None:
            arr = arr[:, spec.component]
        else:
            arr = np.hypot(arr[:, 0], arr[:, 1])
    arr = arr.reshape(-1)
    if spec.where == "point":
        if spec.categorical:
            return arr[tri[:, 0]]
        return arr[tri].mean(axis=1)
    return arr


# ------------------------------------------------------------------------------------
# Frames
# ------------------------------------------------------------------------------------


@dataclass
class FrameData:
    number: int
    time: float
    xy: np.ndarray                # points (n, 2)
    tri: np.ndarray               # (m, 3)
    values: np.ndarray | None     # per triangle
    cracks: tuple | None          # (segments (k,2,2), state (k,), damage (k,))
    water: tuple | None = None    # (positions (n,2), value (n,), time) of the water frame


def read_mesh(path: Path):
    try:
        return meshio.read(str(path))
    except Exception as e:  # noqa: BLE001
        raise lib.InputError(f"{path}: cannot read ({e})") from e


def triangles_of(mesh) -> np.ndarray:
    blocks = [cb.data for cb in mesh.cells if cb.type == "triangle"]
    if not blocks:
        return np.empty((0, 3), dtype=int)
    return np.concatenate(blocks) if len(blocks) > 1 else blocks[0]


def mesh_time(mesh, fallback: float) -> float:
    if math.isfinite(fallback):
        return fallback
    tv = mesh.field_data.get("TimeValue") if hasattr(mesh, "field_data") else None
    try:
        return float(np.asarray(tv).reshape(-1)[0])
    except Exception:  # noqa: BLE001
        return math.nan


def read_cracks(path: Path | None):
    if path is None:
        return None
    m = read_mesh(path)
    segs = []
    state = []
    damage = []
    pts = np.asarray(m.points)[:, :2]
    for i, cb in enumerate(m.cells):
        if cb.type != "line":
            continue
        segs.append(pts[cb.data])
        n = len(cb.data)

        def get(name, default):
            d = m.cell_data.get(name)
            if d is None:
                return np.full(n, default, dtype=float)
            return np.asarray(d[i], dtype=float).reshape(-1)

        state.append(get("state", 0.0))
        damage.append(get("damage", 0.0))
    if not segs:
        return None
    segs, state, damage = np.concatenate(segs), np.concatenate(state), np.concatenate(damage)
    keep = (state >= 0.5) | (damage > 1e-3)  # only what is drawn: intact, undamaged joints are not
    return segs[keep].astype(np.float32), state[keep], damage[keep].astype(np.float32)


def select_frames(frames: list[lib.Frame], spec: str) -> list[lib.Frame]:
    spec = spec.strip().lower()
    if spec in ("all", ""):
        return frames
    by_num = {f.number: f for f in frames}
    nums: list[int] = []
    first, last = frames[0].number, frames[-1].number
    for item in spec.split(","):
        item = item.strip()
        if not item:
            continue
        if item == "last":
            nums.append(last)
        elif item == "first":
            nums.append(first)
        elif re.fullmatch(r"\d+", item):
            nums.append(int(item))
        elif re.fullmatch(r"\d+\s*[-:]\s*\d+", item):
            a, b = (int(x) for x in re.split(r"[-:]", item))
            if a > b:
                a, b = b, a
            nums += [n for n in by_num if a <= n <= b]
        else:
            raise lib.InputError(f"--frames {spec}: cannot read '{item}' (use all, last, first, N, N,M or A-B)")
    missing = [n for n in nums if n not in by_num]
    if missing:
        raise lib.InputError(
            f"--frames {spec}: no frame {', '.join(map(str, missing))}; the run has frames {first}..{last}"
        )
    seen = set()
    return [by_num[n] for n in nums if not (n in seen or seen.add(n))]


def parse_floats(text: str, n: int, opt: str) -> list[float]:
    try:
        v = [float(x) for x in text.split(",")]
    except ValueError:
        v = []
    if len(v) != n or not all(math.isfinite(x) for x in v):
        raise lib.InputError(f"{opt} {text}: expected {n} comma-separated numbers")
    return v


# ------------------------------------------------------------------------------------
# Gauges (marker at the gauge's current position)
# ------------------------------------------------------------------------------------


def gauge_tracks(out: Path, scenario: dict):
    gauges = ((scenario.get("output") or {}).get("gauges")) if isinstance(scenario.get("output"), dict) else None
    if not isinstance(gauges, list) or not gauges:
        return []
    try:
        h = lib.read_history(out / "history.csv")
    except lib.InputError:
        h = None
    tracks = []
    for g in gauges:
        try:
            name = str(g["name"])
            x0, y0 = float(g["at"][0]), float(g["at"][1])
        except (KeyError, TypeError, ValueError, IndexError):
            continue
        ux = uy = None
        if h is not None and h.has(f"{name}_displacement_x_m") and h.has(f"{name}_displacement_y_m"):
            ux, uy = h.col(f"{name}_displacement_x_m"), h.col(f"{name}_displacement_y_m")
        tracks.append((name, x0, y0, None if h is None else h.time, ux, uy))
    return tracks


def gauge_position(track, t: float):
    name, x0, y0, ht, ux, uy = track
    if ux is None or ht is None or not math.isfinite(t) or ht.size == 0:
        return x0, y0
    return x0 + float(np.interp(t, ht, ux)), y0 + float(np.interp(t, ht, uy))


# ------------------------------------------------------------------------------------
# Rendering
# ------------------------------------------------------------------------------------


def water_line(w) -> list[tuple[float, float]] | None:
    """The piezometric line of one `water:` section (docs/theory.md §8), None when dry."""
    if not isinstance(w, dict) or w.get("dry"):
        return None
    if "line" in w:
        return [(float(x), float(z)) for x, z in w["line"]]
    if "level" in w:
        return [(-math.inf, float(w["level"])), (math.inf, float(w["level"]))]
    return None


def water_schedule(scenario: dict, summary: dict | None = None) -> list[tuple[float, list[tuple[float, float]] | None]]:
    """(stage end time, piezometric line or None) of each stage, in order: from the run's
    summary (the water as run, --set included), else from the scenario file."""
    if summary and isinstance(summary.get("water"), list):
        out = []
        for st in summary["water"]:
            pts = st.get("piezometric_line_m")
            line = None
            if pts:
                line = ([(-math.inf, pts[0][1]), (math.inf, pts[0][1])] if len(pts) == 1
                        else [(float(x), float(z)) for x, z in pts])
            out.append((float(st.get("end_s", math.inf)), line))
        return out
    top = scenario.get("water")
    stages = scenario.get("stages") or [{"duration": (scenario.get("time") or {}).get("end", math.inf)}]
    out, t = [], 0.0
    for st in stages:
        st = st if isinstance(st, dict) else {}
        t += float(st.get("duration", math.inf))
        out.append((t, water_line(st.get("water", top))))
    return out


def water_polyline(line, x0: float, x1: float) -> np.ndarray:
    """The line over [x0, x1]: its vertices inside, interpolated (held) at the ends."""
    xs = np.array([p[0] for p in line])
    zs = np.array([p[1] for p in line])
    if not np.isfinite(xs).all():  # a level
        return np.array([[x0, zs[0]], [x1, zs[0]]])
    inside = (xs > x0) & (xs < x1)
    x = np.concatenate([[x0], xs[inside], [x1]])
    return np.column_stack([x, np.interp(x, xs, zs)])


WATER_BAR = 115  # px of the water's colour bar right of the rock's


def category_colors(n: int, without_blue: bool) -> list:
    """n distinct colours for categories; without the blues (tab10's blue and cyan, tab20's
    blue pairs) when the water is drawn in blue."""
    base = matplotlib.colormaps["tab10" if n <= (8 if without_blue else 10) else "tab20"]
    blue = {0, 9} if base.N == 10 else {0, 1, 18, 19}
    idx = [i for i in range(base.N) if not (without_blue and i in blue)]
    return [base(idx[i % len(idx)]) for i in range(n)]


def time_format(times: list[float]) -> str:
    ts = np.array([t for t in times if math.isfinite(t)])
    if ts.size >= 2:
        step = float(np.min(np.diff(np.unique(ts)))) if np.unique(ts).size > 1 else 1.0
    else:
        step = 1.0
    nd = int(min(6, max(1, -math.floor(math.log10(step) + 1e-9)))) if step > 0 else 3
    return f"{{:.{nd}f}}"


class Renderer:
    def __init__(self, args, out: Path):
        self.a = args
        self.out = out
        self.render_dir = out / "render"
        self.summary = lib.read_summary(out)
        self.scenario = lib.load_yaml(lib.find_scenario(out, self.summary))
        self.run_title = self.summary.get("title") or out.name

    def log(self, msg: str) -> None:
        if not self.a.quiet:
            print(msg, flush=True)

    def load(self):
        out = self.out
        frames = lib.read_pvd(out / "fields.pvd") or lib.glob_frames(out / "fields", "fields")
        if not frames:
            raise lib.InputError(
                f"{out / 'fields.pvd'}: no field frames (was the run made with --no-fields?)"
            )
        cracks = lib.read_pvd(out / "cracks.pvd") or lib.glob_frames(out / "cracks", "cracks")
        crack_by_num = {c.number: c for c in cracks}
        selected = select_frames(frames, self.a.frames)
        selected_nums = {f.number for f in selected}

        first = read_mesh(selected[0].path)
        self.spec = resolve_field(self.a.field, first)
        if self.spec.array is None and not cracks:
            self.log("note: no damage array in the fields and no cracks files: drawing the mesh only")

        lo, hi = math.inf, -math.inf
        cats: set[int] = set()
        bb = [math.inf, -math.inf, math.inf, -math.inf]
        data: list[FrameData] = []
        self.all_times: list[float] = []
        prev_tri = None
        # Every frame contributes to colour limits and view box; only selected ones are kept.
        for fr in frames:
            m = first if fr is selected[0] else read_mesh(fr.path)
            tri = triangles_of(m)
            xy = np.asarray(m.points)[:, :2]
            used = xy[np.unique(tri)] if tri.size else xy
            if used.size:
                bb = [min(bb[0], used[:, 0].min()), max(bb[1], used[:, 0].max()),
                      min(bb[2], used[:, 1].min()), max(bb[3], used[:, 1].max())]
            vals = field_values(self.spec, m, tri)
            if vals is not None and vals.size:
                fin = vals[np.isfinite(vals)]
                if fin.size:
                    if self.spec.categorical:
                        cats.update(int(v) for v in np.unique(fin))
                    lo, hi = min(lo, float(fin.min())), max(hi, float(fin.max()))
            cr = None
            cpath = crack_by_num.get(fr.number)
            if cpath is None and cracks and math.isfinite(fr.time):
                near = min(cracks, key=lambda c: abs(c.time - fr.time) if math.isfinite(c.time) else math.inf)
                if math.isfinite(near.time) and abs(near.time - fr.time) <= 1e-9 + 1e-6 * abs(fr.time):
                    cpath = near
            if cpath is not None and not self.a.no_cracks and fr.number in selected_nums:
                cr = read_cracks(cpath.path)
            if fr.number in selected_nums:
                if prev_tri is not None and prev_tri.shape == tri.shape and np.array_equal(prev_tri, tri):
                    tri = prev_tri  # same connectivity as the previous frame: share it
                prev_tri = tri
                data.append(FrameData(fr.number, mesh_time(m, fr.time), xy.astype(np.float32), tri,
                                      None if vals is None else vals.astype(np.float32), cr))
            self.all_times.append(mesh_time(m, fr.time))
        self.has_cracks = bool(cracks) and not self.a.no_cracks
        self.frames = data
        self.model_box = bb if math.isfinite(bb[0]) else [-math.inf, math.inf, -math.inf, math.inf]
        self.load_water()
        if self.a.clim:
            lo, hi = parse_floats(self.a.clim, 2, "--clim")
        elif self.spec.array is not None and not self.spec.categorical:
            if not math.isfinite(lo):
                lo, hi = 0.0, 1.0
            if self.spec.signed and lo < 0 < hi:
                lo, hi = -max(-lo, hi), max(-lo, hi)
            elif not self.spec.signed:
                lo = min(0.0, lo) if lo >= 0 else lo
            if hi <= lo:
                hi = lo + (abs(lo) if lo != 0 else 1.0) * 1e-6 + 1e-30
        self.lo, self.hi = lo, hi
        self.cats = sorted(cats)
        if self.a.bbox:
            x0, x1, y0, y1 = parse_floats(self.a.bbox, 4, "--bbox")
            if not (x1 > x0 and y1 > y0):
                raise lib.InputError(f"--bbox {self.a.bbox}: need xmin < xmax and ymin < ymax")
            self.bbox = [x0, x1, y0, y1]
        else:
            if not math.isfinite(bb[0]):
                bb = [0, 1, 0, 1]
            pad = 0.02 * max(bb[1] - bb[0], bb[3] - bb[2], 1e-12)
            self.bbox = [bb[0] - pad, bb[1] + pad, bb[2] - pad, bb[3] + pad]

    def load_water(self) -> None:
        """The water frame of each selected frame (matched by time) and the water's colour
        limits over every water frame."""
        self.has_water = False
        wframes = [] if self.a.water == "none" else wat.water_frames(self.out)
        if not wframes:
            return
        match = wat.match_by_time([(fd.number, fd.time) for fd in self.frames], wframes)
        wanted = {id(w) for w in match.values()}
        read: dict[int, tuple] = {}
        sample, first_xy = [], None
        x0, x1, y0, y1 = self.model_box
        for w in wframes:
            xy, vals = wat.read_water_frame(w.path, self.a.water)
            if first_xy is None:
                first_xy = xy
            # Particles that left the model (a leak) fall freely: they would set the scale.
            inside = (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1) & np.isfinite(vals)
            v = vals[inside]
            sample.append(v[:: max(1, v.size // 20000)])
            if id(w) in wanted:
                read[id(w)] = (xy, vals, w.time)
        for fd in self.frames:
            w = match.get(fd.number)
            fd.water = read.get(id(w)) if w is not None else None
        self.has_water = True
        pooled = np.concatenate(sample) if sample else np.empty(0)
        # The 99th percentile of every particle of every frame, not the max: the bulk of the water
        # keeps its shades; the few splashing fastest saturate (the bar's arrow).
        hi = float(np.percentile(pooled, 99)) if pooled.size else 0.0
        self.water_lo, self.water_hi = 0.0, hi if hi > 0 else 1.0
        if self.a.water_clim:
            self.water_lo, self.water_hi = parse_floats(self.a.water_clim, 2, "--water-clim")
            if not self.water_hi > self.water_lo:
                raise lib.InputError(f"--water-clim {self.a.water_clim}: need lo < hi")
        self.water_dp = wat.particle_spacing(self.summary, first_xy)

    # -------------------------------------------------------------- moving water
    def rock_colormap(self, name: str):
        """The rock's colour map: the usual one, or one without blue when the water is drawn."""
        if not self.has_water:
            return matplotlib.colormaps[name]
        if name == "RdBu_r":
            return matplotlib.colormaps["PiYG_r"]
        ylorbr = matplotlib.colormaps["YlOrBr"]  # from its 15%: rock at rest still shows on white
        return ListedColormap(ylorbr(np.linspace(0.15, 1.0, 256)), name="rock")

    def build_water(self, W: int, right: int, bottom: int, axh: float, H: int) -> None:
        """The particles and their colour bar: over the rock, under the joints; each a disc of
        diameter dp, so that water at rest just reaches the faces and water inside a solid shows."""
        self.water_sc = None
        if not self.has_water:
            return
        blues = matplotlib.colormaps["Blues"]  # from its 35%: slow water is still clearly blue
        cmap = ListedColormap(blues(np.linspace(0.35, 1.0, 256)), name="water")
        label, unit = wat.WATER_VALUES[self.a.water]
        self.water_factor, unit = lib.autoscale(self.water_hi, unit)
        norm = Normalize(self.water_lo * self.water_factor, self.water_hi * self.water_factor)
        self.ax.apply_aspect()
        box = self.ax.get_window_extent()
        px_per_m = box.width / (self.ax.get_xlim()[1] - self.ax.get_xlim()[0])
        d_px = max(1.5, self.water_dp * px_per_m)
        size = (d_px * 72.0 / self.savedpi) ** 2
        self.water_sc = self.ax.scatter(np.empty(0), np.empty(0), s=size, c=np.empty(0), cmap=cmap, norm=norm,
                                        marker="o", linewidths=0, zorder=2)
        wcax = self.fig.add_axes([(W - right + 22 + WATER_BAR) / W, bottom / H, 18 / W, axh / H])
        cb = self.fig.colorbar(self.water_sc, cax=wcax, extend="max")
        cb.set_label(lib.axis_label(label, unit))
        cb.formatter.set_useMathText(True)

    def view_metadata(self, fd: FrameData) -> dict[str, str]:
        """Where the axes are in the PNG, so that a tool can find a point in the picture."""
        self.ax.apply_aspect()  # the limits as drawn (equal aspect widens one of them)
        box = self.ax.get_window_extent()
        H = self.fig.get_size_inches()[1] * self.savedpi
        x0, x1 = self.ax.get_xlim()
        y0, y1 = self.ax.get_ylim()
        view = (f"axes_px {box.x0:.2f} {H - box.y1:.2f} {box.x1:.2f} {H - box.y0:.2f} "
                f"xlim {x0!r} {x1!r} ylim {y0!r} {y1!r}")
        wt = "" if fd.water is None else repr(float(fd.water[2]))
        return {"dsdem:view": view, "dsdem:water_time": wt}

    # -------------------------------------------------------------- figure
    def build_figure(self):
        lib.setup_style()
        plt.rcParams["axes.grid"] = False
        dpi = 100
        W = int(self.a.width) // 2 * 2
        left, right, top, bottom = 80, 150, 56, 56
        if self.spec.categorical:  # room for the category names next to the colour bar
            longest = max((len(str(v)) for v in self.category_names().values()), default=4)
            right = max(right, min(360, 60 + 8 * longest))
        if self.has_water:  # room for the water's colour bar
            right += WATER_BAR
        x0, x1, y0, y1 = self.bbox
        aspect = (y1 - y0) / (x1 - x0)
        axw = W - left - right
        axh = axw * aspect
        max_h = 0.75 * W
        if axh > max_h:  # tall model: shrink the axes width, keep the figure width
            axh = max_h
            axw = axh / aspect
        axh = max(axh, 200)
        H = int(math.ceil((axh + top + bottom) / 2.0)) * 2
        self.fig = plt.figure(figsize=(W / dpi, H / dpi), dpi=dpi)
        ax_left = left + (W - left - right - axw) / 2
        self.ax = self.fig.add_axes([ax_left / W, bottom / H, axw / W, axh / H])
        self.cax = self.fig.add_axes([(W - right + 22) / W, bottom / H, 18 / W, axh / H])
        ax = self.ax
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_facecolor("white")
        for s in ("top", "right"):
            ax.spines[s].set_visible(True)
        self.savedpi = dpi

        spec = self.spec
        self.factor = 1.0
        if spec.array is None:  # damage without triangle damage: grey mesh, cracks carry colour
            ylorrd = matplotlib.colormaps["YlOrRd"]  # from its 25%: slight damage still shows on grey
            self.cmap = ListedColormap(ylorrd(np.linspace(0.25, 1.0, 256)), name="damage")
            self.norm = Normalize(0.0, 1.0)
            face = "0.88"
            ntri = max((f.tri.shape[0] for f in self.frames), default=0)
            if ntri <= 3000:  # small meshes: show the elements
                self.poly = PolyCollection([], facecolors=face, edgecolors="0.75", linewidths=0.2, zorder=1)
            else:  # fine meshes: edges would only darken the picture
                self.poly = PolyCollection([], facecolors=face, edgecolors="face", linewidths=0.5,
                                           antialiaseds=False, zorder=1)
            sm = matplotlib.cm.ScalarMappable(norm=self.norm, cmap=self.cmap)
            cb = self.fig.colorbar(sm, cax=self.cax)
            cb.set_label("Joint damage (–)")
        elif spec.categorical:
            cats = self.cats or [0]
            names = self.category_names()
            colors = category_colors(len(cats), without_blue=self.has_water)
            self.cat_index = {c: i for i, c in enumerate(cats)}
            self.cmap = ListedColormap(colors)
            self.norm = BoundaryNorm(np.arange(len(cats) + 1) - 0.5, len(cats))
            self.poly = PolyCollection([], cmap=self.cmap, norm=self.norm, edgecolors="face", linewidths=0.5, antialiaseds=False, zorder=1)
            cb = self.fig.colorbar(self.poly, cax=self.cax, ticks=range(len(cats)))
            cb.ax.set_yticklabels([names.get(c, str(c)) for c in cats])
            cb.ax.tick_params(length=0)
        else:
            self.factor, unit = lib.autoscale(max(abs(self.lo), abs(self.hi)), spec.unit)
            cmap_name = "RdBu_r" if (spec.signed and self.lo < 0 < self.hi) else "turbo"
            self.cmap = self.rock_colormap(cmap_name)
            self.norm = Normalize(self.lo * self.factor, self.hi * self.factor)
            self.poly = PolyCollection([], cmap=self.cmap, norm=self.norm, edgecolors="face", linewidths=0.5, antialiaseds=False, zorder=1)
            cb = self.fig.colorbar(self.poly, cax=self.cax, extend="neither")
            cb.set_label(lib.axis_label(spec.label, unit))
            cb.formatter.set_useMathText(True)
        ax.add_collection(self.poly)

        if spec.array is None:  # the damage view: joints carry the colour scale of the bar
            self.crack_cmap = self.cmap
            self.crack_range = (0.0, 1.0)
        else:  # over a coloured field: damage as a grey ramp, light (slight) to dark (near failure)
            self.crack_cmap = matplotlib.colormaps["Greys"]
            self.crack_range = (0.35, 0.85)
        self.cracks_damaged = LineCollection([], linewidths=1.3, zorder=3)
        self.cracks_broken = LineCollection([], colors="0.05", linewidths=1.6, zorder=4)
        ax.add_collection(self.cracks_damaged)
        ax.add_collection(self.cracks_broken)
        if self.has_cracks:
            handles = [
                Line2D([], [], color="0.05", lw=1.8, label="broken joint"),
                Line2D([], [], color=self.crack_cmap(sum(self.crack_range) / 2), lw=1.8, label="damaged joint"),
            ]
            ax.legend(handles=handles, loc="lower left", fontsize=9, framealpha=0.85)

        self.gauges = [] if self.a.no_gauges else gauge_tracks(self.out, self.scenario)
        self.gauge_artists = []
        for g in self.gauges:
            (mk,) = ax.plot([], [], "o", ms=6, mfc="white", mec="black", mew=1.2, zorder=6)
            tx = ax.annotate(g[0], xy=(0, 0), xytext=(5, 5), textcoords="offset points", fontsize=9, zorder=6,
                             bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))
            self.gauge_artists.append((mk, tx))

        # The water at rest of the frame's stage: its piezometric line over a light fill.
        self.water = water_schedule(self.scenario if isinstance(self.scenario, dict) else {}, self.summary)
        self.water_fill = PolyCollection([], facecolors=(0.35, 0.6, 0.9, 0.18), edgecolors="none", zorder=0.5)
        ax.add_collection(self.water_fill)
        (self.water_curve,) = ax.plot([], [], color=(0.1, 0.35, 0.75), lw=1.4, zorder=5)
        if any(line is not None for _, line in self.water):
            leg = ax.get_legend()
            handles = list(getattr(leg, "legend_handles", None) or getattr(leg, "legendHandles", [])) if leg else []
            handles.append(Line2D([], [], color=(0.1, 0.35, 0.75), lw=1.6, label="piezometric line"))
            ax.legend(handles=handles, loc="lower left", fontsize=9, framealpha=0.85)

        self.title_left = ax.set_title("", loc="left")
        ax.set_title(self.run_title if len(self.run_title) <= 70 else self.run_title[:67] + "...",
                     loc="right", fontsize=9.5, color="0.4", fontweight="normal")
        self.tfmt = time_format(self.all_times)
        self.build_water(W, right, bottom, axh, H)

    def category_names(self) -> dict[int, str]:
        if self.spec.array == "material_id":
            return lib.material_names(self.summary, self.scenario)
        if self.spec.array == "zone":
            return ZONE_NAMES
        return {}

    def draw(self, fd: FrameData) -> Path:
        spec = self.spec
        verts = fd.xy[fd.tri]
        self.poly.set_verts(verts)
        if fd.values is not None:
            if spec.categorical:
                idx = np.array([self.cat_index.get(int(v), 0) for v in fd.values]) if fd.values.size else fd.values
                self.poly.set_array(np.asarray(idx, dtype=float))
            else:
                self.poly.set_array(fd.values * self.factor)
        if fd.cracks is not None:
            segs, state, dmg = fd.cracks
            broken = state >= 0.5
            dmg_mask = (~broken) & (dmg > 1e-3)
            self.cracks_broken.set_segments(segs[broken])
            self.cracks_damaged.set_segments(segs[dmg_mask])
            lo, hi = self.crack_range
            self.cracks_damaged.set_color(self.crack_cmap(lo + (hi - lo) * np.clip(dmg[dmg_mask], 0, 1)))
        else:
            self.cracks_broken.set_segments([])
            self.cracks_damaged.set_segments([])
        self.draw_water(fd.time)
        if self.water_sc is not None:
            if fd.water is not None:
                self.water_sc.set_offsets(fd.water[0])
                self.water_sc.set_array(fd.water[1] * self.water_factor)
            else:
                self.water_sc.set_offsets(np.empty((0, 2)))
                self.water_sc.set_array(np.empty(0))
        for g, (mk, tx) in zip(self.gauges, self.gauge_artists):
            x, y = gauge_position(g, fd.time)
            mk.set_data([x], [y])
            tx.xy = (x, y)
        tstr = f"t = {self.tfmt.format(fd.time)} s" if math.isfinite(fd.time) else f"frame {fd.number}"
        self.title_left.set_text(f"{spec.label}, {tstr}")
        self.render_dir.mkdir(parents=True, exist_ok=True)
        path = self.render_dir / f"{safe_name(spec.key)}_{fd.number:06d}.png"
        tmp = path.with_name(path.stem + ".tmp.png")
        self.fig.savefig(tmp, dpi=self.savedpi, metadata=self.view_metadata(fd), pil_kwargs={"compress_level": 3})
        tmp.replace(path)
        return path

    def draw_water(self, time: float) -> None:
        line = None
        for end, stage_line in self.water:
            line = stage_line
            if not math.isfinite(time) or time <= end * (1 + 1e-9):
                break
        if line is None:
            self.water_curve.set_data([], [])
            self.water_fill.set_verts([])
            return
        x0, x1, y0, _ = self.bbox
        pts = water_polyline(line, x0, x1)
        self.water_curve.set_data(pts[:, 0], pts[:, 1])
        if self.has_water:  # the moving water shows itself: no fill at rest under it
            self.water_fill.set_verts([])
        else:
            below = np.vstack([pts, [[x1, y0], [x0, y0]]])
            self.water_fill.set_verts([below] if (pts[:, 1] > y0).any() else [])

    def movie(self, pngs: list[Path]) -> Path:
        return make_movie(pngs, self.render_dir / f"{safe_name(self.spec.key)}.mp4", self.a.fps)

    def draw_range(self, lo: int, hi: int) -> list[Path]:
        if not hasattr(self, "fig"):
            self.build_figure()
        return [self.draw(fd) for fd in self.frames[lo:hi]]

    def run(self) -> list[Path]:
        self.load()
        n = len(self.frames)
        jobs = max(1, min(self.a.jobs or (os.cpu_count() or 1), 8, n // 4 or 1))
        written: list[Path] = []
        if jobs > 1:
            # Frames are independent: fork workers that each build the figure once and draw a
            # contiguous share (the frame data is inherited, nothing is pickled but paths).
            import multiprocessing as mp

            global _RENDERER
            _RENDERER = self
            chunk = max(1, min(10, math.ceil(n / (jobs * 3))))
            ranges = [(i, min(n, i + chunk)) for i in range(0, n, chunk)]
            with mp.get_context("fork").Pool(jobs) as pool:
                for k, paths in enumerate(pool.imap(_draw_range, ranges)):
                    written += paths
                    if not self.a.quiet and n > 5:
                        print(f"  rendered {len(written)}/{n} frames", flush=True)
        else:
            self.build_figure()
            for i, fd in enumerate(self.frames):
                written.append(self.draw(fd))
                if not self.a.quiet and n > 5 and ((i + 1) % max(1, n // 10) == 0 or i + 1 == n):
                    print(f"  rendered {i + 1}/{n} frames", flush=True)
            plt.close(self.fig)
        outputs = list(written)
        if self.a.movie:
            outputs.append(self.movie(written))
        return outputs


_RENDERER: Renderer | None = None


def _draw_range(r: tuple[int, int]) -> list[Path]:
    return _RENDERER.draw_range(*r)


def make_movie(pngs: list[Path], mp4: Path, fps: float) -> Path:
    """The PNGs, in order, as an H.264 mp4 (ffmpeg), written under a temporary name then renamed."""
    ffmpeg = shutil.which("ffmpeg")
    if not ffmpeg:
        raise lib.InputError("ffmpeg not found on PATH: install ffmpeg, or render without --movie")
    with tempfile.TemporaryDirectory(prefix="dsdem-movie-") as tmp:
        for i, p in enumerate(pngs):
            os.symlink(p.resolve(), Path(tmp) / f"{i:06d}.png")
        part = mp4.with_name(mp4.stem + ".part.mp4")
        cmd = [
            ffmpeg, "-y", "-loglevel", "error", "-framerate", str(fps),
            "-i", str(Path(tmp) / "%06d.png"),
            "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2,format=yuv420p",
            "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "20", "-movflags", "+faststart",
            str(part),
        ]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            part.unlink(missing_ok=True)
            raise RuntimeError(f"ffmpeg failed ({r.returncode}): {r.stderr.strip()}")
        part.replace(mp4)
    return mp4


def is_3d(out: Path) -> bool:
    """A 3D run: summary.json says "dimension": 3 (a plane run's has no such key), or, before the
    run has written its summary, the first field frame holds tetrahedra and no triangles."""
    summary = lib.read_summary(out)
    if summary:
        return summary.get("dimension") == 3
    frames = lib.read_pvd(out / "fields.pvd") or lib.glob_frames(out / "fields", "fields")
    if not frames:
        return False
    types = {cb.type for cb in read_mesh(frames[0].path).cells}
    return "tetra" in types and "triangle" not in types


def safe_name(s: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", s)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Render the field frames of a dsdem run to PNG (and mp4).")
    ap.add_argument("out", help="output folder of a dsdem run")
    ap.add_argument("--field", default="velocity",
                    help="velocity, displacement, material, stress, damage, or any VTU array name (default velocity)")
    ap.add_argument("--frames", default="all", help="all, last, first, N, N,M or A-B (frame numbers; default all)")
    ap.add_argument("--movie", action="store_true", help="also assemble OUT/render/<field>.mp4 with ffmpeg")
    ap.add_argument("--fps", type=float, default=10.0, help="movie frame rate (default 10)")
    ap.add_argument("--bbox", help="view box xmin,xmax,ymin,ymax in m (default: all frames)")
    ap.add_argument("--clim", help="colour limits lo,hi in SI units (default: all frames)")
    ap.add_argument("--width", type=int, default=1280, help="image width in pixels (default 1280)")
    ap.add_argument("--jobs", type=int, default=0, help="parallel render processes (default: all cores, at most 8)")
    ap.add_argument("--water", choices=["speed", "pressure", "none"], default="speed",
                    help="colour the moving water's particles by speed or pressure, or do not draw them (default speed)")
    ap.add_argument("--water-clim", help="the water's colour limits lo,hi in SI units (default: 0 to the 99th "
                                         "percentile of every particle in the model over all frames)")
    ap.add_argument("--section", help="3D runs: the section's plane, x|y|z[=COORDINATE in m] (default y through "
                                      "the model's centre)")
    ap.add_argument("--no-cracks", action="store_true", help="do not draw joints")
    ap.add_argument("--no-gauges", action="store_true", help="do not mark the gauges")
    ap.add_argument("--quiet", action="store_true", help="print nothing but errors")
    a = ap.parse_args(argv)
    if not (a.fps > 0):
        raise lib.InputError(f"--fps {a.fps}: must be positive")
    if a.width < 320 or a.width > 8000:
        raise lib.InputError(f"--width {a.width}: must be between 320 and 8000 pixels")
    out = Path(a.out)
    if not out.is_dir():
        raise lib.InputError(f"{out}: no such output folder")
    if is_3d(out):  # tetrahedra: VTK's offscreen rendering (render_fields3d.py)
        import render_fields3d

        render_dir = out / "render"
        outputs = render_fields3d.render(a, out, sys.modules[__name__])
    else:
        if a.section:
            raise lib.InputError(f"--section {a.section}: a plane run has no sections (3D runs only)")
        r = Renderer(a, out)
        render_dir = r.render_dir
        outputs = r.run()
    if not a.quiet:
        pngs = [p for p in outputs if p.suffix == ".png"]
        print(f"wrote {len(pngs)} image(s) to {render_dir}:")
        for p in pngs if len(pngs) <= 12 else pngs[:3] + [Path("...")] + pngs[-3:]:
            print(f"  {p}")
        for p in outputs:
            if p.suffix == ".mp4":
                print(f"wrote movie {p}")
    return 0


if __name__ == "__main__":
    lib.run_main(main)
