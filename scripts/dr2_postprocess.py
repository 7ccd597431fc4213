#!/usr/bin/python3
"""Post-processing of a Dr2 slope run (examples/dr2, docs/dr2.md).

    dr2_postprocess.py OUT [--block-height 10] [--mode NAME] [--geometry JSON] [--quiet] [--movie [--dsdem EXE]]

Reads OUT/history.csv, OUT/fields.pvd (+ OUT/fields/*.vtu) and OUT/summary.json and
writes OUT/dr2.json, merges its keys into OUT/summary.json (the runner's keys kept; its
own gauge list renamed `gauges_from_run_start`) and writes plots in OUT/dr2_plots/:

  gauges.png     gauge displacement and velocity magnitudes against time (paper Figs. 17/19/21)
  snapshots.png  the broken mass at the paper's stages (Figs. 16/18/20)
  deposit.png    final deposit profile over the original ground
  energy.png     kinetic energy of the run and the 1 % duration threshold
  (--movie)      OUT/render/material.mp4 and its frames, made by `dsdem render`

The river bed, channel, intake and original ground below are those of examples/dr2/dr2.geo;
--geometry JSON replaces them for another profile (keys `ground` [[x, z], ...] right bank to
left bank, `river_x` [x_right, x_left], `river_bed_z`, `channel_top_z`, `intake` [x, z],
optional `plot_x` [x_min, x_max]), e.g. examples/dr2/sensitivity/dr2_gentle.json.

Definitions (all times from the start of the earthquake stage, i.e. the earthquake's t = 0):
  gauges[].max_displacement_m      max |u(t) - u(t0)| over the dynamic stage (t0 = its start),
                                   so the gravity settling is not counted
  gauges[].peak_velocity_mps       max |v| over the dynamic stage
  gauges[].time_of_peak_velocity_s time of that peak
  mean_max_displacement_m          mean over the four gauges
  duration_s                       first time after the kinetic-energy peak at which the
                                   kinetic energy falls below 1 % of that peak
  river_blocked_time_s             first field frame in which debris (zone-A material)
                                   reaches at least --block-height (default 10 m) above the
                                   river bed (745 m) in every 10 m column of the river bed
                                   x = 720..810 m, linearly interpolated between frames on
                                   the least-filled column; null if never
  deposit_area_in_channel_m2       area of zone-A triangles (final frame) whose centroid is
                                   inside the channel: the open region of the original
                                   profile between the banks below 790 m
  intake_debris_height_m           final frame: highest point of moved zone-A material (moved
                                   more than 5 m) over the original ground within 10 m
                                   (horizontally) of the intake (715, 750.8)
  intake_blocked                   intake_debris_height_m >= --block-height (the same 10 m as
                                   for the river): debris covers the intake
  intake_reached                   any moved zone-A material within 15 m of the intake (even
                                   one fragment)
  intake_debris_by_group           final frame: moved zone-A triangles (moved more than 5 m) with a
                                   node within 10 m (horizontally) of the intake, counted per
                                   surface group (plate, column, mudstone, deposit): what covers it
  deposit_profile                  final frame: {x_m, thickness_m}, every 5 m over the plot's x range,
                                   the top of the zone-A material moved more than 5 m since the
                                   start of the earthquake above the original ground (0 where
                                   none): what `dsdem ensemble` turns into P(thicker than d) along x
  moved_by_group                   final frame: per zone-A surface group, [triangles moved more
                                   than 5 m since the start of the earthquake, triangles]
Uses only numpy, meshio and matplotlib (Agg).
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import dsdem_post as dp  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RIVER_BED_Z = 745.0
RIVER_X = (720.0, 810.0)
CHANNEL_TOP_Z = 790.0
INTAKE = (715.0, 750.8333)
# Original ground (examples/dr2/dr2.geo), right bank to left bank.
GROUND = np.array([(0, 1128), (250, 1102), (398, 1080), (436, 1074), (474, 960), (540, 914), (560, 900),
                   (690, 780), (720, 745), (810, 745), (880, 860), (980, 1040), (1298, 1169)], float)
PLOT_X = (330.0, 900.0)   # x range of the snapshot and deposit plots and of the movie
PAPER = {  # reference/paper_results.json
    "shear_sliding": {"mean": 160, "gauges": [170, 60, 150, 150], "v": {"gauge1": 22.0, "gauge2": 17.5},
                      "duration": 35.0, "blocked": 24.3},
    "local_collapse": {"mean": 210},
    "slip_j1": {"mean": 140, "max": 220, "v": {"gauge1": 17.0, "gauge2": 22.0}, "duration": 35.0},
}


def set_geometry(path: str) -> dict:
    """Replace the river bed, channel, intake and original ground of dr2.geo by those of
    another profile (--geometry; keys in the module docstring)."""
    global GROUND, RIVER_BED_Z, RIVER_X, CHANNEL_TOP_Z, INTAKE, PLOT_X
    g = json.loads(Path(path).read_text())
    GROUND = np.array(g["ground"], float)
    RIVER_BED_Z = float(g["river_bed_z"])
    RIVER_X = tuple(float(v) for v in g["river_x"])
    CHANNEL_TOP_Z = float(g["channel_top_z"])
    INTAKE = tuple(float(v) for v in g["intake"])
    PLOT_X = tuple(float(v) for v in g.get("plot_x", PLOT_X))
    return g


def channel_polygon() -> np.ndarray:
    """The open region of the original ground below CHANNEL_TOP_Z between the banks: the
    ground vertices below it around the river bed, closed by the two bank crossings."""
    def x_at(z, a, b):
        return a[0] + (z - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
    ir = int(np.nonzero((GROUND[:, 0] == RIVER_X[0]) & (GROUND[:, 1] == RIVER_BED_Z))[0][0])
    il = ir
    while GROUND[ir - 1, 1] < CHANNEL_TOP_Z:
        ir -= 1
    while GROUND[il + 1, 1] < CHANNEL_TOP_Z:
        il += 1
    xr = x_at(CHANNEL_TOP_Z, GROUND[ir - 1], GROUND[ir])
    xl = x_at(CHANNEL_TOP_Z, GROUND[il], GROUND[il + 1])
    return np.array([(xr, CHANNEL_TOP_Z)] + [tuple(p) for p in GROUND[ir:il + 1]] + [(xl, CHANNEL_TOP_Z)])


def inside(poly: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Even-odd rule, p: (n, 2)."""
    x, y = p[:, 0], p[:, 1]
    res = np.zeros(len(p), bool)
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        cond = (y1 > y) != (y2 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        res ^= cond & (x < xc)
    return res


def read_history(out: Path):
    with open(out / "history.csv") as f:
        header = f.readline().strip().split(",")
    data = np.genfromtxt(out / "history.csv", delimiter=",", skip_header=1)
    if data.ndim == 1:
        data = data[None, :]
    return {h: data[:, i] for i, h in enumerate(header)}


def read_frames(out: Path):
    pvd = out / "fields.pvd"
    if not pvd.exists():
        return []
    txt = pvd.read_text()
    return [(float(t), out / f) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', txt)]


def load_frame(path: Path):
    import meshio
    m = meshio.read(path)
    tri = m.cells_dict["triangle"]
    zone = np.asarray(m.cell_data_dict["zone"]["triangle"]).ravel()
    mat = np.asarray(m.cell_data_dict["material_id"]["triangle"]).ravel()
    disp = np.asarray(m.point_data["displacement_m"])[:, :2]
    return m.points[:, :2], tri, zone, mat, disp


def frame_groups(path: Path) -> np.ndarray:
    """group_id of each triangle of a frame (index into the mesh's physical groups)."""
    import meshio
    return np.asarray(meshio.read(path).cell_data_dict["group_id"]["triangle"]).ravel().astype(int)


def group_names(out: Path) -> dict[int, str]:
    """group_id -> name: dsdem numbers the physical groups in the order of the mesh's
    $PhysicalNames section (OUT/dr2.msh, written by the run). Empty if there is no mesh."""
    names: dict[int, str] = {}
    msh = next(iter(sorted(out.glob("*.msh"))), None)
    if msh is None:
        return names
    lines = msh.read_text(errors="replace").splitlines()
    if "$PhysicalNames" not in lines:
        return names
    i = lines.index("$PhysicalNames")
    for k in range(int(lines[i + 1])):
        names[k] = lines[i + 2 + k].split('"')[1]
    return names


def tri_area(P, tri):
    a, b, c = P[tri[:, 0]], P[tri[:, 1]], P[tri[:, 2]]
    return 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def fill_heights(P, tri, zone):
    """Debris top above the river bed in each 10 m column of the river bed."""
    edges = np.arange(RIVER_X[0], RIVER_X[1] + 1e-9, 10.0)
    top = np.zeros(len(edges) - 1)
    sel = zone == 0
    pts = P[np.unique(tri[sel].ravel())]
    for i in range(len(edges) - 1):
        m = (pts[:, 0] >= edges[i]) & (pts[:, 0] < edges[i + 1]) & (pts[:, 1] < CHANNEL_TOP_Z + 60)
        top[i] = (pts[m, 1].max() - RIVER_BED_Z) if m.any() else 0.0
    return top


def surface_profile(P, tri, xs):
    """Highest material point per x bin (upper envelope of the deformed mesh)."""
    top = np.full(len(xs) - 1, np.nan)
    # Sample every triangle edge (large bedrock triangles span several bins).
    s = np.linspace(0.0, 1.0, 12)[:, None]
    pts = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        A, B = P[tri[:, a]], P[tri[:, b]]
        pts.append((A[None, :, :] * (1 - s[:, :, None]) + B[None, :, :] * s[:, :, None]).reshape(-1, 2))
    pts = np.concatenate(pts)
    idx = np.digitize(pts[:, 0], xs) - 1
    ok = (idx >= 0) & (idx < len(xs) - 1)
    np.fmax.at(top, idx[ok], pts[ok, 1])
    return top


def final_water_line(summary: dict) -> np.ndarray | None:
    """The last stage's piezometric line from summary.json's water block, over the plot's x range."""
    stages = summary.get("water") if isinstance(summary.get("water"), list) else []
    pts = stages[-1].get("piezometric_line_m") if stages else None
    if not pts:
        return None
    if len(pts) == 1:
        return np.array([[PLOT_X[0], pts[0][1]], [PLOT_X[1], pts[0][1]]])
    pts = np.array(pts, dtype=float)
    xs = np.unique(np.concatenate([[PLOT_X[0], PLOT_X[1]], pts[(pts[:, 0] > PLOT_X[0]) & (pts[:, 0] < PLOT_X[1]), 0]]))
    return np.column_stack([xs, np.interp(xs, pts[:, 0], pts[:, 1])])


def make_movie(out: Path, dsdem: str | None, quiet: bool) -> None:
    """Animation of the run: `dsdem render OUT --field material --movie` over the slope."""
    import shutil
    import subprocess
    exe = dsdem or str(Path(__file__).resolve().parent.parent / "build" / "dsdem")
    if not Path(exe).exists():
        exe = shutil.which("dsdem") or exe
    cmd = [exe, "render", str(out), "--field", "material", "--movie", "--bbox", f"{PLOT_X[0]:g},{PLOT_X[1]:g},720,1100",
           "--width", "960", "--jobs", "1"] + (["-q"] if quiet else [])
    r = subprocess.run(cmd)
    if r.returncode != 0:
        print(f"warning: `{' '.join(cmd)}` failed ({r.returncode}); no animation", file=sys.stderr)


SUMMARY_KEYS = ("gauges", "mean_max_displacement_m", "duration_s", "river_blocked_time_s",
                "deposit_area_in_channel_m2", "intake_blocked", "intake_debris_height_m", "intake_reached",
                "river_block_height_m", "earthquake_start_s", "deposit_profile")


def merge_summary(sp: Path, res: dict) -> None:
    """Merge the Dr2 keys into the runner's OUT/summary.json (dsdem_post.merge_summary).

    The runner's own keys are kept; its `gauges` (times from the start of the run,
    displacement from t = 0) is kept as `gauges_from_run_start` and `gauges` becomes the
    Dr2 definition above (from the start of the earthquake). Running this twice is safe."""
    keys = {k: res[k] for k in SUMMARY_KEYS}
    keys["dr2_postprocess"] = {"mode": res["mode"], "definitions": "scripts/dr2_postprocess.py docstring"}
    dp.merge_summary(str(sp.parent), keys, renamed={"gauges": "gauges_from_run_start"})


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--block-height", type=float, default=10.0, help="debris height over the river bed that blocks it, m")
    ap.add_argument("--mode", default=None, help="shear_sliding | local_collapse | slip_j1 (default: from the scenario name)")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--movie", action="store_true",
                    help="also make the animation OUT/render/material.mp4 with `dsdem render` (needs ffmpeg)")
    ap.add_argument("--dsdem", default=None, help="dsdem executable for --movie (default: build/dsdem, then PATH)")
    ap.add_argument("--geometry", default=None,
                    help="JSON with the river bed, channel, intake and ground of another profile "
                         "(default: examples/dr2/dr2.geo's), e.g. examples/dr2/sensitivity/dr2_gentle.json")
    args = ap.parse_args(argv)
    if args.geometry:
        set_geometry(args.geometry)
    out = Path(args.out)
    sp = out / "summary.json"
    summary = json.loads(sp.read_text()) if sp.exists() else {"scenario": str(out)}  # a run still going
    mode = args.mode or next((k for k in PAPER if k in str(summary.get("scenario", ""))), None)
    h = read_history(out)
    t = h["time_s"]
    stage = h["stage"]
    dyn = stage >= stage.max() if stage.max() > 0 else np.ones_like(t, bool)
    i0 = int(np.argmax(dyn))
    t0 = t[i0 - 1] if i0 > 0 else t[0]   # the earthquake starts at the end of the gravity stage
    td = t[dyn] - t0
    names = [re.sub(r"_displacement_x_m$", "", k) for k in h if k.endswith("_displacement_x_m")]
    gauges = []
    series = {}
    for g in names:
        ux, uy = h[f"{g}_displacement_x_m"], h[f"{g}_displacement_y_m"]
        vx, vy = h[f"{g}_velocity_x_m_per_s"], h[f"{g}_velocity_y_m_per_s"]
        ref = max(i0 - 1, 0)
        u = np.hypot(ux[dyn] - ux[ref], uy[dyn] - uy[ref])
        v = np.hypot(vx[dyn], vy[dyn])
        k = int(np.argmax(v))
        gauges.append({"name": g, "max_displacement_m": float(u.max()), "peak_velocity_mps": float(v[k]),
                       "time_of_peak_velocity_s": float(td[k]), "final_displacement_m": float(u[-1])})
        series[g] = (u, v)
    mean_max = float(np.mean([g["max_displacement_m"] for g in gauges])) if gauges else None
    ke = h["kinetic_J_per_m"][dyn]
    kpk = int(np.argmax(ke))
    below = np.nonzero(ke[kpk:] < 0.01 * ke[kpk])[0]
    duration = float(td[kpk + below[0]]) if len(below) else None

    # Field frames: river blocking, deposit in the channel, intake, snapshots.
    frames = [(tt - t0, p) for tt, p in read_frames(out) if tt >= t0 - 1e-9]
    blocked = None
    prev = None
    fill_hist = []
    for tt, p in frames:
        P, tri, zone, mat, disp = load_frame(p)
        fh = fill_heights(P, tri, zone)
        fill_hist.append((tt, float(fh.min())))
        if blocked is None and fh.min() >= args.block_height:
            if prev is not None and prev[1] < args.block_height:
                blocked = prev[0] + (tt - prev[0]) * (args.block_height - prev[1]) / (fh.min() - prev[1])
            else:
                blocked = tt
        prev = (tt, float(fh.min()))
    area_channel = None
    intake_blocked = intake_reached = intake_height = None
    intake_groups = moved_groups = deposit_profile = None
    if frames:
        P, tri, zone, mat, disp = load_frame(frames[-1][1])
        cen = P[tri].mean(axis=1)
        A = tri_area(P, tri)
        inch = inside(channel_polygon(), cen) & (zone == 0)
        area_channel = float(A[inch].sum())
        moved = np.linalg.norm(disp[tri].mean(axis=1), axis=1) > 5.0
        near = np.hypot(cen[:, 0] - INTAKE[0], cen[:, 1] - INTAKE[1]) < 15.0
        intake_reached = bool(np.any(moved & near & (zone == 0)))
        # Debris thickness over the original ground at the intake (|x - 715| <= 10 m).
        pts = P[np.unique(tri[moved & (zone == 0)].ravel())]
        m = np.abs(pts[:, 0] - INTAKE[0]) <= 10.0
        intake_height = float(max(0.0, (pts[m, 1] - np.interp(pts[m, 0], GROUND[:, 0], GROUND[:, 1])).max())) \
            if m.any() else 0.0
        intake_blocked = intake_height >= args.block_height
        # What moved, and what lies at the intake, per surface group (displacement since the
        # start of the earthquake, as for the gauges).
        f0 = next((p for tt, p in frames if tt >= -1e-9), frames[0][1])
        disp0 = load_frame(f0)[4]
        moved_eq = np.linalg.norm((disp - disp0)[tri].mean(axis=1), axis=1) > 5.0
        grp = frame_groups(frames[-1][1])
        gname = group_names(out)
        moved_groups, intake_groups = {}, {}
        near_i = np.any(np.abs(P[tri][:, :, 0] - INTAKE[0]) <= 10.0, axis=1)
        for g in np.unique(grp[zone == 0]):
            sel = (grp == g) & (zone == 0)
            name = gname.get(int(g), str(int(g)))
            moved_groups[name] = [int(np.sum(moved_eq & sel)), int(np.sum(sel))]
            intake_groups[name] = int(np.sum(moved_eq & sel & near_i))
        xs = np.arange(PLOT_X[0], PLOT_X[1] + 1, 5.0)
        debris = tri[moved_eq & (zone == 0)]
        top = surface_profile(P, debris, xs) if len(debris) else np.full(len(xs) - 1, np.nan)
        xc = 0.5 * (xs[1:] + xs[:-1])
        thick = np.nan_to_num(np.maximum(0.0, top - np.interp(xc, GROUND[:, 0], GROUND[:, 1])), nan=0.0)
        deposit_profile = {"x_m": [float(x) for x in xc], "thickness_m": [float(h) for h in thick]}

    res = {
        "mode": mode,
        "scenario": summary.get("scenario"),
        "earthquake_start_s": float(t0),
        "gauges": gauges,
        "mean_max_displacement_m": mean_max,
        "duration_s": duration,
        "river_blocked_time_s": blocked,
        "river_block_height_m": args.block_height,
        "deposit_area_in_channel_m2": area_channel,
        "intake_blocked": intake_blocked,
        "intake_debris_height_m": intake_height,
        "intake_reached": intake_reached,
        "intake_debris_by_group": intake_groups,
        "moved_by_group": moved_groups,
        "deposit_profile": deposit_profile,
        "broken_joints": summary.get("broken_joints"),
        "fragments": summary.get("fragments"),
        "elements": summary.get("elements"),
        "wall_time_s": summary.get("wall_time_s"),
        "element_steps_per_s": summary.get("element_steps_per_s"),
        "dt_s": summary.get("dt_s"),
        "dt_controlled_by": summary.get("dt_controlled_by"),
        "end_time_s": summary.get("end_time_s"),
        "paper": PAPER.get(mode),
    }
    if args.geometry:
        res["geometry"] = {"file": args.geometry, "river_x": list(RIVER_X), "river_bed_z": RIVER_BED_Z,
                           "intake": list(INTAKE)}
    (out / "dr2.json").write_text(json.dumps(res, indent=2))
    if sp.exists():
        merge_summary(sp, res)

    pd = out / "dr2_plots"
    pd.mkdir(exist_ok=True)
    fig, ax = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for g in names:
        u, v = series[g]
        ax[0].plot(td, u, label=g)
        ax[1].plot(td, v, label=g)
    ax[0].set_ylabel("displacement |u| (m)")
    ax[1].set_ylabel("velocity |v| (m/s)")
    ax[1].set_xlabel("time from the start of the earthquake (s)")
    ax[0].legend()
    ax[0].set_title(f"Dr2 {mode or ''}: gauges (mean max displacement {mean_max:.0f} m)" if mean_max else "gauges")
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(pd / "gauges.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.semilogy(td, np.maximum(ke, 1e-3))
    ax.axhline(0.01 * ke[kpk], color="r", ls="--", label="1 % of peak")
    if duration is not None:
        ax.axvline(duration, color="k", ls=":", label=f"duration {duration:.1f} s")
    ax.set_xlabel("time from the start of the earthquake (s)")
    ax.set_ylabel("kinetic energy (J/m)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(pd / "energy.png", dpi=110)
    plt.close(fig)

    if frames:
        wanted = [0, 5, 10, 17, 24, 35]
        picks = []
        for w in wanted:
            j = int(np.argmin([abs(tt - w) for tt, _ in frames]))
            if frames[j] not in picks:
                picks.append(frames[j])
        nc = 2
        nr = math.ceil(len(picks) / nc)
        fig, axs = plt.subplots(nr, nc, figsize=(12, 3.2 * nr), squeeze=False)
        for a, (tt, p) in zip(axs.ravel(), picks):
            P, tri, zone, mat, disp = load_frame(p)
            a.plot(GROUND[:, 0], GROUND[:, 1], "k-", lw=0.8)
            s = zone == 0
            a.tripcolor(P[:, 0], P[:, 1], tri[s], facecolors=mat[s].astype(float), cmap="tab10", vmin=0, vmax=9,
                        edgecolors="none")
            a.set_xlim(*PLOT_X)
            a.set_ylim(720, 1100)
            a.set_aspect("equal")
            a.set_title(f"t = {tt:.1f} s")
        for a in axs.ravel()[len(picks):]:
            a.axis("off")
        fig.tight_layout()
        fig.savefig(pd / "snapshots.png", dpi=100)
        plt.close(fig)

        P, tri, zone, mat, disp = load_frame(frames[-1][1])
        xs = np.arange(PLOT_X[0], PLOT_X[1] + 1, 5.0)
        top = surface_profile(P, tri, xs)
        fig, ax = plt.subplots(figsize=(10, 4.5))
        ax.plot(GROUND[:, 0], GROUND[:, 1], "k--", lw=1, label="original ground")
        ax.plot(0.5 * (xs[1:] + xs[:-1]), top, "r-", lw=1.5, label=f"final surface (t = {frames[-1][0]:.1f} s)")
        s = zone == 0
        ax.tripcolor(P[:, 0], P[:, 1], tri[s], facecolors=mat[s].astype(float), cmap="tab10", vmin=0, vmax=9,
                     edgecolors="none", alpha=0.6)
        ax.fill(*channel_polygon().T, color="tab:blue", alpha=0.2, label="river channel (< 790 m)")
        ax.plot(*INTAKE, "k^", label="intake")
        line = final_water_line(summary)
        if line is not None:  # the last stage's piezometric line (docs/theory.md §8)
            ax.plot(line[:, 0], line[:, 1], color=(0.1, 0.35, 0.75), lw=1.2, label="piezometric line")
        ax.set_xlim(*PLOT_X)
        ax.set_ylim(720, 1100)
        ax.set_aspect("equal")
        ax.legend(loc="upper right", fontsize=8)
        ax.set_title("final deposit profile")
        fig.tight_layout()
        fig.savefig(pd / "deposit.png", dpi=110)
        plt.close(fig)

    if args.movie and frames:
        make_movie(out, args.dsdem, args.quiet)

    if not args.quiet:
        print(json.dumps({k: res[k] for k in ("mean_max_displacement_m", "duration_s", "river_blocked_time_s",
                                              "deposit_area_in_channel_m2", "intake_blocked",
                                              "intake_debris_height_m", "intake_reached",
                                              "intake_debris_by_group", "moved_by_group")}, indent=1))
        for g in gauges:
            print(f"  {g['name']}: umax {g['max_displacement_m']:.1f} m, vpeak {g['peak_velocity_mps']:.1f} m/s "
                  f"at {g['time_of_peak_velocity_s']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
