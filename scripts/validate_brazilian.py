#!/usr/bin/python3
"""Post-processing of the Brazilian disc test (examples/brazilian_disc, DESIGN.md §7).

    python3 scripts/validate_brazilian.py OUT [--scenario examples/brazilian_disc/scenario.yaml]

Reads OUT/history.csv, OUT/cracks.csv, OUT/fields/*.vtu and OUT/cracks/*.vtu of
`dsdem run`, writes OUT/validation.json with the case's numbers and the acceptance
checks, and PNG plots in OUT/plots/:

  load_displacement.png   load on the top plate against its displacement
  stress_diameters.png    sigma_xx, sigma_yy along both diameters before cracking vs
                          the Hondros / point-load elastic solution
  cracks_first.png        broken joints at the first crack
  cracks_through.png      broken joints once the crack runs through the disc

Definitions (docs/validation.md):
  load P               mean of the y reactions on the two plates (N per m in plane
                       strain): the load on the disc without the inertia of the disc
                       rattling between the contacts (each plate's own peak is reported
                       too)
  tensile strength     sigma_t = 2 P_peak / (pi D t)
  crack initiation     first frame in which a joint within 0.5 R of the centre has
                       started to soften (damage > 0)
  first crack          first joint that breaks (cracks.csv)
  through crack        first time the disc is in two pieces each larger than 10 % of
                       its area (fragment field of the frames, timed by the fragment
                       count of the history)
  stress check         at the frame nearest 50 % of the peak load (elastic), stresses
                       averaged over the triangles within one local element size of
                       each sample point, error |num - analytic| / max(|analytic|,
                       sigma_0) with sigma_0 = 2P/(pi D t), on the loaded diameter
                       for |y| <= 0.8 R (0.2 R and more from the plates) and on the
                       unloaded diameter for |x| <= 0.9 R.
"""
from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dsdem_post as dp  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402


def hondros(rho: np.ndarray, alpha: float, diameter: str) -> tuple[np.ndarray, np.ndarray]:
    """Hondros (1959): disc loaded by a uniform radial pressure over two arcs of half
    angle alpha centred on the y axis. Returns (sigma_xx, sigma_yy) / sigma_0 with
    sigma_0 = 2P/(pi D t), tension positive, at rho = r/R on the loaded (y) or the
    unloaded (x) diameter. alpha -> 0 gives the point-load solution."""
    rho = np.asarray(rho, dtype=float)
    r2 = rho * rho
    if alpha < 1e-9:  # point load
        if diameter == "loaded":
            return np.ones_like(rho), -(3 + r2) / (1 - r2)
        return ((1 - r2) / (1 + r2)) ** 2, -(1 - r2) * (3 + r2) / (1 + r2) ** 2
    s2, c2, ta = math.sin(2 * alpha), math.cos(2 * alpha), math.tan(alpha)
    if diameter == "loaded":
        a = (1 - r2) * s2 / (1 - 2 * r2 * c2 + r2 * r2)
        b = np.arctan((1 + r2) / (1 - r2) * ta)
        return (a - b) / alpha, -(a + b) / alpha
    a = (1 - r2) * s2 / (1 + 2 * r2 * c2 + r2 * r2)
    b = np.arctan((1 - r2) / (1 + r2) * ta)
    return (a - b) / alpha, -(a + b) / alpha


def contact_half_angle(P: float, R: float, E: float, nu: float) -> float:
    """Half angle of the contact arc of a disc pressed on a rigid flat (plane-strain
    Hertz: half width b = sqrt(4 P R / (pi E')), E' = E / (1 - nu^2))."""
    Ep = E / (1 - nu * nu)
    b = math.sqrt(4 * P * R / (math.pi * Ep))
    return math.asin(min(1.0, b / R))


def sample_line(f: dp.Fields, mask: np.ndarray, pts: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Area-weighted mean stress of the triangles (in mask) whose reference centroid lies
    within radius of each reference point; NaN where none."""
    c = f.centroid0[mask]
    s = f.stress[mask]
    a = f.area0[mask]
    out = np.full((len(pts), 3), np.nan)
    for i, (p, r) in enumerate(zip(pts, radius)):
        d = np.hypot(c[:, 0] - p[0], c[:, 1] - p[1])
        w = a * (d <= r)
        if w.sum() > 0:
            out[i] = (s * w[:, None]).sum(axis=0) / w.sum()
    return out


def local_size(f: dp.Fields, mask: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Element size sqrt(2 A) of the triangle nearest each point."""
    c = f.centroid0[mask]
    h = np.sqrt(2 * f.area0[mask])
    out = np.empty(len(pts))
    for i, p in enumerate(pts):
        out[i] = h[np.argmin(np.hypot(c[:, 0] - p[0], c[:, 1] - p[1]))]
    return out


def draw_state(ax, f: dp.Fields, disc: np.ndarray, seg: dict, title: str, scale_stress: float) -> None:
    from matplotlib.collections import PolyCollection

    polys = f.x[f.tri]
    sxx = f.stress[:, 0]
    pc = PolyCollection(polys[disc], array=sxx[disc] / 1e6, cmap="coolwarm", edgecolors="none")
    pc.set_clim(-scale_stress / 1e6, scale_stress / 1e6)
    ax.add_collection(pc)
    others = ~disc
    ax.add_collection(PolyCollection(polys[others], facecolors="0.6", edgecolors="0.3", linewidths=0.3))
    broken = seg["state"] == 1
    lines = np.stack([seg["a"][broken], seg["b"][broken]], axis=1)
    ax.add_collection(LineCollection(lines, colors="k", linewidths=1.6))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return pc


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="output folder of dsdem run")
    ap.add_argument("--scenario", help="scenario file (default: the one named in OUT/summary.json)")
    ap.add_argument("--disc", default="disc", help="surface group of the disc")
    ap.add_argument("--plate", default="top_plate", help="surface group of the moving plate")
    ap.add_argument("--bottom-plate", default="bottom_plate", help="surface group of the fixed plate")
    ap.add_argument("--no-plots", action="store_true")
    args = ap.parse_args()
    out = args.out

    sc = dp.load_scenario(out, args.scenario)
    summary = dp.read_summary(out)
    jd = dict(sc.get("joints", {}).get("default", {}))
    jd.update(sc.get("joints", {}).get("groups", {}).get(args.disc, {}) or {})
    ft, GI = float(jd["ft"]), float(jd["GI"])
    mat_name = next(r["material"] for r in sc["regions"] if r["group"] == args.disc)
    mat = sc["materials"][mat_name]
    E, nu = float(mat["E"]), float(mat["nu"])
    mesh = sc["mesh"]
    plane_stress = mesh.get("plane", "strain") == "stress"
    t = float(mesh.get("thickness", 1.0)) if plane_stress else 1.0

    hist = dp.read_history(out)
    time = hist["time_s"]
    P_top = -dp.column(hist, f"{args.plate}_reaction_y")
    force_unit = dp.column_name(hist, f"{args.plate}_reaction_y").split("_reaction_y_")[1]
    try:
        P_bottom = dp.column(hist, f"{args.bottom_plate}_reaction_y")
    except KeyError:
        P_bottom = P_top
    # The load on the disc: the mean of the two plates' reactions. Each plate's reaction
    # alone also carries the inertia of the disc rattling between the two contacts
    # (antiphase, about +-1 % of the peak, period about 0.5 ms); the mean cancels it.
    P = 0.5 * (P_top + P_bottom)
    frames = dp.read_pvd(out, "fields")
    crack_frames = dp.read_pvd(out, "cracks")
    f0 = dp.Fields(frames[0][1])
    disc0 = f0.zone == 0
    # Disc geometry from the mesh: centre and radius of the discrete zone.
    pts_disc = f0.X[np.unique(f0.tri[disc0])]
    centre = 0.5 * (pts_disc.min(axis=0) + pts_disc.max(axis=0))
    R = 0.5 * (pts_disc[:, 1].max() - pts_disc[:, 1].min())
    D = 2 * R
    scale = math.pi * D * t / 2  # P = scale * sigma_t

    # Plate displacement from the prescribed velocity history: integrate the plate's
    # velocity = the frames' displacement of the plate nodes; use the history time and
    # the frames to build u(t) (frames are exact, interpolate in between).
    plate_nodes = np.unique(f0.tri[(f0.zone != 0) & (f0.centroid0[:, 1] > centre[1])])
    u_frames = []
    for tf, path in frames:
        import meshio

        m = meshio.read(path)
        u_frames.append(-m.point_data["displacement_m"][plate_nodes, 1].mean())
    u_frames = np.array(u_frames)
    t_frames = np.array([tf for tf, _ in frames])
    u_plate = np.interp(time, t_frames, u_frames)

    i_peak = int(np.argmax(P))
    P_peak = float(P[i_peak])
    sigma_t = P_peak / scale
    rel_err = (sigma_t - ft) / ft

    # Crack initiation (the paper's "crack at the centre when the normal stress reaches
    # the tensile strength"): first crack frame in which a joint within 0.5 R of the
    # centre has started to soften (damage > 0); its position is that of the most
    # damaged such joint. Resolution: the frame interval.
    i_init, init_pos = None, None
    for tf, path in crack_frames:
        seg = dp.read_segments(path)
        mid = 0.5 * (seg["a"] + seg["b"]) - centre
        central = np.hypot(mid[:, 0], mid[:, 1]) <= 0.5 * R
        dmg = np.where(central, seg["damage"], 0.0)
        if dmg.max() > 0.0:
            i_init = int(np.argmin(np.abs(time - tf)))
            init_pos = mid[int(np.argmax(dmg))].tolist()
            break
    cracks = dp.read_cracks(out)
    first = cracks[0] if cracks else None

    # Through crack: the broken joints within 0.2 R of the loaded diameter cover it from
    # 0.2 R below the top plate to 0.2 R above the bottom one with no gap longer than
    # 0.1 R. (Under the plates the material is in compression: the split ends in a
    # crushed wedge there and the halves stay bonded through it, so the fragment count
    # of the history does not see the split.) Timed by the crack log.
    t_through, frame_through = None, None
    ys = []
    for c in cracks:
        dx, dy = c["x_m"] - centre[0], c["y_m"] - centre[1]
        if abs(dx) > 0.2 * R:
            continue
        ys.append(dy)
        cover = np.sort(np.array([y for y in ys if abs(y) <= 0.8 * R] + [-0.8 * R, 0.8 * R]))
        if np.max(np.diff(cover)) <= 0.1 * R:
            t_through = c["time_s"]
            frame_through = dp.frame_after(frames, t_through) or frames[-1]
            break
    disc_area = f0.area0[disc0].sum()
    pieces_end = None
    f_end = dp.Fields(frames[-1][1])
    if f_end.fragment is not None:
        pieces_end = (f_end.pieces(f_end.zone == 0) / disc_area).tolist()

    # Stress check before cracking: frame nearest 50 % of the peak (on the rising branch).
    rising = [(tf, p) for tf, p in frames if tf <= time[i_peak]]
    P_frames = np.interp([tf for tf, _ in rising], time, P)
    k = int(np.argmin(np.abs(P_frames - 0.5 * P_peak)))
    t_check, path_check = rising[k]
    P_mean = float(P_frames[k])
    sigma0 = P_mean / scale
    fc = dp.Fields(path_check)
    disc = fc.zone == 0
    alpha = contact_half_angle(P_mean / t, R, E, nu)
    checks = {}
    curves = {}
    for name, axis, lim in (("loaded", 1, 0.8), ("unloaded", 0, 0.9)):
        rho = np.linspace(-0.95, 0.95, 77)
        pts = np.zeros((len(rho), 2))
        pts[:, axis] = rho * R
        pts += centre
        h = local_size(fc, disc, pts)
        num = sample_line(fc, disc, pts, h) / sigma0
        an_xx, an_yy = hondros(rho, alpha, name)
        pt_xx, pt_yy = hondros(rho, 0.0, name)
        inside = np.abs(rho) <= lim + 1e-12
        err_xx = np.abs(num[:, 0] - an_xx) / np.maximum(np.abs(an_xx), 1.0)
        err_yy = np.abs(num[:, 1] - an_yy) / np.maximum(np.abs(an_yy), 1.0)
        checks[name] = {
            "range_rho": lim,
            "max_error_sigma_xx": float(np.nanmax(err_xx[inside])),
            "max_error_sigma_yy": float(np.nanmax(err_yy[inside])),
            "rms_error_sigma_xx": float(np.sqrt(np.nanmean(err_xx[inside] ** 2))),
            "rms_error_sigma_yy": float(np.sqrt(np.nanmean(err_yy[inside] ** 2))),
        }
        curves[name] = (rho, num, an_xx, an_yy, pt_xx, pt_yy, inside)
    centre_sxx = float(sample_line(fc, disc, centre[None, :], local_size(fc, disc, centre[None, :]))[0, 0])

    stress_ok = all(max(c["max_error_sigma_xx"], c["max_error_sigma_yy"]) <= 0.05 for c in checks.values())
    first_pos = None if first is None else [first["x_m"] - centre[0], first["y_m"] - centre[1]]
    first_dist = None if first is None else math.hypot(*first_pos)

    # Through crack along the loaded diameter: the covering of the through-crack test
    # also holds with a band of 0.1 R (all broken joints by the end of the run), and the
    # mean |x| of the broken joints with |y| <= 0.8 R at the through crack.
    def covered(band: float) -> bool:
        ys = [c["y_m"] - centre[1] for c in cracks if abs(c["x_m"] - centre[0]) <= band * R]
        cover = np.sort(np.array([y for y in ys if abs(y) <= 0.8 * R] + [-0.8 * R, 0.8 * R]))
        return bool(np.max(np.diff(cover)) <= 0.1 * R)

    along_diameter = t_through is not None and covered(0.1)
    through_offset = None
    if t_through is not None:
        xs = [abs(c["x_m"] - centre[0]) / R for c in cracks
              if c["time_s"] <= t_through and abs(c["y_m"] - centre[1]) <= 0.8 * R]
        through_offset = float(np.mean(xs)) if xs else None

    result = {
        "case": "brazilian_disc",
        "scenario": summary.get("scenario"),
        "radius_m": R,
        "thickness_m": t,
        "force_unit": force_unit,
        "elements": summary.get("elements"),
        "joints": summary.get("joints"),
        "dt_s": summary.get("dt_s"),
        "wall_time_s": summary.get("wall_time_s"),
        "peak_load_N": P_peak,
        "peak_load_top_plate_N": float(P_top.max()),
        "peak_load_bottom_plate_N": float(P_bottom.max()),
        "time_of_peak_s": float(time[i_peak]),
        "plate_displacement_at_peak_m": float(u_plate[i_peak]),
        "tensile_strength_Pa": sigma_t,
        "input_tensile_strength_Pa": ft,
        "relative_error": rel_err,
        "crack_initiation_load_N": None if i_init is None else float(P[i_init]),
        "crack_initiation_strength_Pa": None if i_init is None else float(P[i_init] / scale),
        "t_crack_initiation_s": None if i_init is None else float(time[i_init]),
        "crack_initiation_position_m": init_pos,
        "t_first_crack_s": None if first is None else first["time_s"],
        "first_crack_position_m": first_pos,
        "first_crack_distance_from_centre_over_R": None if first is None else first_dist / R,
        "first_crack_mode": None if first is None else first["mode"],
        "t_through_crack_s": t_through,
        "through_crack_mean_offset_from_loaded_diameter_over_R": through_offset,
        "through_crack_within_0.1R_of_loaded_diameter": along_diameter,
        "broken_joints": summary.get("broken_joints"),
        "disc_pieces_area_fraction_at_end": None if pieces_end is None else pieces_end[:6],
        "fragments": summary.get("fragments"),
        "energy_balance_error": summary.get("energy_balance_error"),
        "stress_check": {
            "time_s": t_check,
            "load_N": P_mean,
            "sigma_0_Pa": sigma0,
            "centre_sigma_xx_Pa": centre_sxx,
            "contact_half_angle_rad": alpha,
            "diameters": checks,
        },
        "acceptance": {
            "relative_error_within_3_percent": abs(rel_err) <= 0.03,
            "first_crack_within_0.1R_of_centre": first_dist is not None and first_dist <= 0.1 * R,
            "through_crack_along_loaded_diameter": along_diameter,
            "stresses_within_5_percent": stress_ok,
        },
    }
    plots = os.path.join(out, "plots")
    os.makedirs(plots, exist_ok=True)
    dp.write_json(os.path.join(out, "validation.json"), result)

    if not args.no_plots:
        # Load-displacement.
        fig, ax = plt.subplots(figsize=(6, 4.2))
        unit = "MN/m" if force_unit == "N_per_m" else "MN"
        ax.plot(u_plate * 1e3, P_top / 1e6, lw=0.6, color="0.6", label="top plate reaction")
        ax.plot(u_plate * 1e3, P / 1e6, lw=1.2, label="load (mean of both plates)")
        ax.axhline(ft * scale / 1e6, color="0.5", ls="--", lw=1, label=r"$P = \pi D t f_t / 2$")
        ax.plot(u_plate[i_peak] * 1e3, P_peak / 1e6, "ro", ms=5, label=f"peak {P_peak / 1e3:.0f} k{unit[1:]}")
        if i_init is not None:
            ax.plot(u_plate[i_init] * 1e3, P[i_init] / 1e6, "ks", ms=5, label="crack initiation")
        if first is not None:
            ax.axvline(np.interp(first["time_s"], time, u_plate) * 1e3, color="C2", lw=0.8, label="first joint broken")
        if t_through is not None:
            ax.axvline(np.interp(t_through, time, u_plate) * 1e3, color="C3", lw=0.8, label="through crack")
        ax.set_xlabel("top plate displacement (mm)")
        ax.set_ylabel(f"load P ({unit})")
        ax.set_xlim(0, min(u_plate[-1], 2.0 * u_plate[i_peak]) * 1e3)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("Brazilian disc: load against the displacement of the top plate", fontsize=10)
        fig.tight_layout()
        fig.savefig(os.path.join(plots, "load_displacement.png"), dpi=130)
        plt.close(fig)

        # Stresses along the diameters.
        fig, axs = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
        for ax, name in zip(axs, ("loaded", "unloaded")):
            rho, num, an_xx, an_yy, pt_xx, pt_yy, inside = curves[name]
            ax.plot(rho, an_xx, "C0-", lw=1.3, label=r"$\sigma_{xx}$ Hondros")
            ax.plot(rho, an_yy, "C1-", lw=1.3, label=r"$\sigma_{yy}$ Hondros")
            ax.plot(rho, pt_xx, "C0:", lw=1, label="point load")
            ax.plot(rho, pt_yy, "C1:", lw=1)
            ax.plot(rho, num[:, 0], "C0o", ms=3.5, mfc="none", label=r"$\sigma_{xx}$ dsdem")
            ax.plot(rho, num[:, 1], "C1s", ms=3.5, mfc="none", label=r"$\sigma_{yy}$ dsdem")
            lim = checks[name]["range_rho"]
            ax.axvspan(-1, -lim, color="0.9")
            ax.axvspan(lim, 1, color="0.9")
            ax.set_xlim(-1, 1)
            ax.set_ylim(-8, 2)
            ax.grid(alpha=0.3)
            ax.set_xlabel("y / R (loaded diameter)" if name == "loaded" else "x / R (unloaded diameter)")
            e = checks[name]
            ax.set_title(f"{name} diameter: max error {100 * e['max_error_sigma_xx']:.1f} % (xx), "
                         f"{100 * e['max_error_sigma_yy']:.1f} % (yy)", fontsize=9)
        axs[0].set_ylabel(r"$\sigma / \sigma_0$,  $\sigma_0 = 2P/(\pi D t)$")
        axs[0].legend(fontsize=7, loc="lower center")
        fig.suptitle(f"Stresses before cracking, P = {P_mean / 1e3:.0f} k{force_unit.replace('_per_', '/')} "
                     f"(t = {t_check * 1e3:.1f} ms); shaded: within 0.2 R of the plates / 0.1 R of the rim", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(plots, "stress_diameters.png"), dpi=130)
        plt.close(fig)

        # Crack snapshots.
        snaps = []
        if first is not None:
            fr = dp.frame_after(frames, first["time_s"]) or frames[-1]
            snaps.append(("cracks_first.png", fr, f"first crack: joint broken at t = {first['time_s'] * 1e3:.2f} ms; "
                                                  f"frame t = {fr[0] * 1e3:.2f} ms"))
        if frame_through is not None:
            snaps.append(("cracks_through.png", frame_through,
                          f"through crack at t = {t_through * 1e3:.2f} ms; frame t = {frame_through[0] * 1e3:.2f} ms"))
        for fname, (tf, path), title in snaps:
            f = dp.Fields(path)
            seg = dp.read_segments(dp.frame_nearest(crack_frames, tf)[1])
            fig, ax = plt.subplots(figsize=(5.2, 5.6))
            pc = draw_state(ax, f, f.zone == 0, seg, title, 3 * ft)
            fig.colorbar(pc, ax=ax, shrink=0.7, label=r"$\sigma_{xx}$ (MPa)")
            fig.tight_layout()
            fig.savefig(os.path.join(plots, fname), dpi=130)
            plt.close(fig)

    def fmt(v, f="{:.4g}"):
        return "-" if v is None else f.format(v)

    print(f"peak load          {P_peak:.6g} {force_unit} at t = {time[i_peak]:.5g} s "
          f"(top plate alone {P_top.max():.6g}, bottom {P_bottom.max():.6g})")
    print(f"tensile strength   {sigma_t / 1e6:.4f} MPa (input {ft / 1e6:.4f} MPa), error {100 * rel_err:+.2f} %")
    print(f"crack initiation   t = {fmt(result['t_crack_initiation_s'])} s at {init_pos} m, "
          f"strength {fmt(result['crack_initiation_strength_Pa'] and result['crack_initiation_strength_Pa'] / 1e6)} MPa")
    print(f"first crack        t = {fmt(result['t_first_crack_s'])} s at {first_pos} m "
          f"({fmt(result['first_crack_distance_from_centre_over_R'], '{:.3f}')} R from the centre)")
    print(f"through crack      t = {fmt(t_through)} s, mean offset {fmt(through_offset, '{:.3f}')} R, "
          f"within 0.1 R of the loaded diameter: {along_diameter}")
    for name, c in checks.items():
        print(f"stress {name:<9}   max error xx {100 * c['max_error_sigma_xx']:.2f} %, yy {100 * c['max_error_sigma_yy']:.2f} %")
    for k, v in result["acceptance"].items():
        print(f"  {'PASS' if v else 'FAIL'}  {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
