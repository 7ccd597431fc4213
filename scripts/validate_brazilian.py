#!/usr/bin/python3
"""Post-processing of the Brazilian disc test (examples/brazilian_disc, docs/validation.md §1).

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
  stress check         at the frame nearest 50 % of the peak load (elastic, long before
                       any joint softens). Analytic field: Hondros (uniform radial
                       pressure on two arcs of half angle alpha, built everywhere in the
                       disc as the superposition of diametral point-load pairs over the
                       arc; on the diameters it equals Hondros' closed form), with alpha
                       from the contact half-width b MEASURED in that frame (the width
                       of the disc rim that overlaps the plate, both plates averaged);
                       the plane-strain Hertz width is reported beside it. Sampling: at
                       77 points along each diameter, the area-weighted mean of the
                       constant (CST) stresses of the triangles whose centroid lies
                       within one local element size of the point (a band about two
                       elements wide), compared with the same weighted mean of the
                       analytic stress averaged over each of those triangles (edge-
                       midpoint rule), i.e. like with like. Error |num - analytic| /
                       max(|analytic|, sigma_0), sigma_0 = 2P/(pi D t), on the loaded
                       diameter for |y| <= 0.8 R (0.2 R and more from the plates) and on
                       the unloaded diameter for |x| <= 0.9 R. Also reported: the same
                       error for each triangle crossed by (or with an edge on) a
                       diameter, and against the closed form on the line itself.
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


def hertz_half_angle(P: float, R: float, E: float, nu: float) -> float:
    """Half angle of the contact arc of a disc pressed on a rigid flat (plane-strain
    Hertz: half width b = sqrt(4 P R / (pi E')), E' = E / (1 - nu^2)); P per unit
    thickness."""
    Ep = E / (1 - nu * nu)
    b = math.sqrt(4 * P * R / (math.pi * Ep))
    return math.asin(min(1.0, b / R))


def measured_half_width(f: dp.Fields, disc: np.ndarray, centre: np.ndarray, R: float) -> list[float]:
    """Contact half-width on each plate (top, bottom) in frame f: the half length of the
    part of the disc rim that overlaps the plate's face (rim nodes of the deformed disc
    beyond the plate face, the ends interpolated linearly between the last rim node
    inside and the first outside). 0 where nothing overlaps."""
    dn = np.unique(f.tri[disc])
    rim = dn[np.hypot(f.X[dn, 0] - centre[0], f.X[dn, 1] - centre[1]) > R * (1 - 1e-6)]
    out = []
    for sgn in (1, -1):
        plate = (~disc) & (sgn * (f.centroid0[:, 1] - centre[1]) > 0)
        pn = np.unique(f.tri[plate])
        face = f.x[pn, 1].min() if sgn > 0 else f.x[pn, 1].max()
        r = rim[sgn * (f.X[rim, 1] - centre[1]) > 0.5 * R]
        # Rim points: the copies of a mesh node (one per triangle in a discrete zone)
        # share a reference position; take their mean x and their largest overlap.
        keys, inv = np.unique(np.round(f.X[r, 0] / R, 9), return_inverse=True)
        ov_all = sgn * (f.x[r, 1] - face)
        ux = np.array([f.x[r[inv == i], 0].mean() for i in range(len(keys))])
        prof = np.array([ov_all[inv == i].max() for i in range(len(keys))])
        k = np.nonzero(prof > 0)[0]
        if len(k) == 0 or k.min() == 0 or k.max() == len(ux) - 1:
            out.append(0.0)
            continue
        i0, i1 = k.min(), k.max()
        xr = ux[i1] + (ux[i1 + 1] - ux[i1]) * prof[i1] / (prof[i1] - prof[i1 + 1])
        xl = ux[i0] + (ux[i0 - 1] - ux[i0]) * prof[i0] / (prof[i0] - prof[i0 - 1])
        out.append(0.5 * (xr - xl))
    return out


def point_pair_field(x: np.ndarray, y: np.ndarray, R: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Disc of radius R (centre at the origin) squeezed by two opposite point loads at
    (0, +-R) (Timoshenko & Goodier): (sigma_xx, sigma_yy, sigma_xy) / sigma_0."""
    r1 = x * x + (R - y) ** 2
    r2 = x * x + (R + y) ** 2
    k = 2 * R  # 2P/(pi t) in units of sigma_0 = P/(pi R t)
    sxx = 1 - k * (x * x * (R - y) / r1 ** 2 + x * x * (R + y) / r2 ** 2)
    syy = 1 - k * ((R - y) ** 3 / r1 ** 2 + (R + y) ** 3 / r2 ** 2)
    sxy = k * (x * (R - y) ** 2 / r1 ** 2 - x * (R + y) ** 2 / r2 ** 2)
    return sxx, syy, sxy


def hondros_field(x: np.ndarray, y: np.ndarray, R: float, alpha: float, n: int = 64) -> np.ndarray:
    """Hondros' disc (uniform radial pressure on the arcs |theta| <= alpha about the y
    axis, both ends) everywhere: the mean of n diametral point-load pairs rotated by
    theta over the arc (superposition, exact as n grows; on the diameters it matches
    the closed form of hondros() to 1e-4). Returns (N, 3): xx, yy, xy over sigma_0."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if alpha < 1e-9:
        return np.stack(point_pair_field(x, y, R), axis=-1)
    acc = np.zeros(x.shape + (3,))
    for th in (np.arange(n) + 0.5) / n * 2 * alpha - alpha:
        c, s = math.cos(th), math.sin(th)
        a, b, q = point_pair_field(c * x - s * y, s * x + c * y, R)
        # back to the x, y frame (rotation by -theta)
        acc[..., 0] += c * c * a + s * s * b + 2 * s * c * q
        acc[..., 1] += s * s * a + c * c * b - 2 * s * c * q
        acc[..., 2] += -s * c * (a - b) + (c * c - s * s) * q
    return acc / n


def band_mean(c: np.ndarray, a: np.ndarray, h: np.ndarray, values: list[np.ndarray], pts: np.ndarray) -> list[np.ndarray]:
    """Area-weighted means of per-triangle values over the triangles whose centroid c
    lies within the local element size (that of the triangle nearest the point) of each
    point; NaN where none."""
    out = [np.full((len(pts), v.shape[1]), np.nan) for v in values]
    for i, p in enumerate(pts):
        d = np.hypot(c[:, 0] - p[0], c[:, 1] - p[1])
        w = a * (d <= h[np.argmin(d)])
        if w.sum() > 0:
            for o, v in zip(out, values):
                o[i] = (v * w[:, None]).sum(axis=0) / w.sum()
    return out


def disc_mask(f: dp.Fields) -> np.ndarray:
    """Triangles of the disc: the discrete zone; for a run with a continuous disc (zone
    'contact', no joints: the elastic reference of docs/validation.md), the surface
    group with the largest area."""
    mask = f.zone == 0
    if mask.any():
        return mask
    groups = np.unique(f.group)
    big = groups[int(np.argmax([f.area0[f.group == g].sum() for g in groups]))]
    return f.group == big


def stress_check(fc: dp.Fields, centre: np.ndarray, R: float, P_mean: float, t: float, E: float, nu: float) -> dict:
    """The elastic stress check of one frame (module docstring): numbers for the JSON and,
    under the key '_curves', the arrays for the plot."""
    scale = math.pi * 2 * R * t / 2
    sigma0 = P_mean / scale
    disc = disc_mask(fc)
    b_meas = measured_half_width(fc, disc, centre, R)
    b_mean = float(np.mean(b_meas))
    alpha_hertz = hertz_half_angle(P_mean / t, R, E, nu)
    alpha = math.asin(min(1.0, b_mean / R)) if b_mean > 0 else alpha_hertz
    # Per-triangle numbers in the disc frame (reference positions; before cracking the
    # disc has moved by well under 0.1 % of R).
    tri = fc.tri[disc]
    Xr = fc.X - centre
    q0, q1, q2 = Xr[tri[:, 0]], Xr[tri[:, 1]], Xr[tri[:, 2]]
    s_num = fc.stress[disc] / sigma0
    s_an = sum(hondros_field(m[:, 0], m[:, 1], R, alpha) for m in (0.5 * (q0 + q1), 0.5 * (q1 + q2), 0.5 * (q2 + q0))) / 3
    cen = fc.centroid0[disc] - centre
    area = fc.area0[disc]
    hsz = np.sqrt(2 * area)

    def stress_err(num, an):
        return np.abs(num - an) / np.maximum(np.abs(an), 1.0)

    checks = {}
    curves = {}
    for name, axis, lim in (("loaded", 1, 0.8), ("unloaded", 0, 0.9)):
        rho = np.linspace(-0.95, 0.95, 77)
        pts = np.zeros((len(rho), 2))
        pts[:, axis] = rho * R
        num, an = band_mean(cen, area, hsz, [s_num, s_an], pts)
        an_xx, an_yy = hondros(rho, alpha, name)
        pt_xx, pt_yy = hondros(rho, 0.0, name)
        inside = np.abs(rho) <= lim + 1e-12
        err = stress_err(num[:, :2], an[:, :2])
        err_line = stress_err(num[:, :2], np.stack([an_xx, an_yy], axis=1))
        # Triangles crossed by the diameter or with an edge on it.
        v = np.stack([q0[:, 1 - axis], q1[:, 1 - axis], q2[:, 1 - axis]], axis=1)
        tol = 1e-9 * R
        crossed = ((v.min(axis=1) < -tol) & (v.max(axis=1) > tol)) | ((np.abs(v) <= tol).sum(axis=1) >= 2)
        crossed &= np.abs(cen[:, axis]) <= lim * R
        err_el = stress_err(s_num[crossed, :2], s_an[crossed, :2])
        worst = int(np.nanargmax(np.where(inside, np.maximum(err[:, 0], err[:, 1]), -1)))
        checks[name] = {
            "range_rho": lim,
            "max_error_sigma_xx": float(np.nanmax(err[inside, 0])),
            "max_error_sigma_yy": float(np.nanmax(err[inside, 1])),
            "rms_error_sigma_xx": float(np.sqrt(np.nanmean(err[inside, 0] ** 2))),
            "rms_error_sigma_yy": float(np.sqrt(np.nanmean(err[inside, 1] ** 2))),
            "worst_rho": float(rho[worst]),
            "max_error_sigma_xx_within_0.7": float(np.nanmax(err[np.abs(rho) <= 0.7 + 1e-12, 0])),
            "max_error_sigma_yy_within_0.7": float(np.nanmax(err[np.abs(rho) <= 0.7 + 1e-12, 1])),
            "against_closed_form_on_the_line": {
                "max_error_sigma_xx": float(np.nanmax(err_line[inside, 0])),
                "max_error_sigma_yy": float(np.nanmax(err_line[inside, 1]))},
            "profile": {"rho": rho, "num_xx": num[:, 0], "num_yy": num[:, 1], "an_xx": an[:, 0], "an_yy": an[:, 1],
                        "error_xx": err[:, 0], "error_yy": err[:, 1]},
            "single_triangles": {
                "count": int(crossed.sum()),
                "max_error_sigma_xx": float(err_el[:, 0].max()),
                "max_error_sigma_yy": float(err_el[:, 1].max()),
                "rms_error_sigma_xx": float(np.sqrt(np.mean(err_el[:, 0] ** 2))),
                "rms_error_sigma_yy": float(np.sqrt(np.mean(err_el[:, 1] ** 2)))},
        }
        curves[name] = (rho, num, an, an_xx, an_yy, pt_xx, pt_yy, err, inside,
                        cen[crossed, axis] / R, s_num[crossed])
    centre_sxx = float(band_mean(cen, area, hsz, [s_num], np.zeros((1, 2)))[0][0, 0] * sigma0)
    return {
        "load_N": P_mean,
        "sigma_0_Pa": sigma0,
        "centre_sigma_xx_Pa": centre_sxx,
        "contact_half_width_measured_m": b_meas,
        "contact_half_width_hertz_m": R * math.sin(alpha_hertz),
        "contact_half_angle_rad": alpha,
        "diameters": checks,
        "passed": all(max(c["max_error_sigma_xx"], c["max_error_sigma_yy"]) <= 0.05 for c in checks.values()),
        "_curves": curves,
    }



def plot_stress(path: str, st: dict, force_unit: str) -> None:
    """sigma_xx, sigma_yy along both diameters (top) and the error of the samples (bottom)."""
    fig, axs = plt.subplots(2, 2, figsize=(10, 6.4), sharex=True,
                            gridspec_kw={"height_ratios": [2.2, 1]})
    for j, name in enumerate(("loaded", "unloaded")):
        ax, ax_e = axs[0, j], axs[1, j]
        rho, num, an, an_xx, an_yy, pt_xx, pt_yy, err, inside, rho_el, s_el = st["_curves"][name]
        ax.plot(rho_el, s_el[:, 0], ".", color="C0", ms=2, alpha=0.35)
        ax.plot(rho_el, s_el[:, 1], ".", color="C1", ms=2, alpha=0.35)
        ax.plot(rho, an_xx, "C0-", lw=1.3, label=r"$\sigma_{xx}$ Hondros")
        ax.plot(rho, an_yy, "C1-", lw=1.3, label=r"$\sigma_{yy}$ Hondros")
        ax.plot(rho, pt_xx, "k:", lw=0.9, label="point load")
        ax.plot(rho, pt_yy, "k:", lw=0.9)
        ax.plot(rho, num[:, 0], "C0o", ms=3.5, mfc="none", label=r"$\sigma_{xx}$ dsdem (band mean)")
        ax.plot(rho, num[:, 1], "C1s", ms=3.5, mfc="none", label=r"$\sigma_{yy}$ dsdem (band mean)")
        ax_e.plot(rho, 100 * err[:, 0], "C0o-", ms=3, lw=0.8, mfc="none", label=r"$\sigma_{xx}$")
        ax_e.plot(rho, 100 * err[:, 1], "C1s-", ms=3, lw=0.8, mfc="none", label=r"$\sigma_{yy}$")
        ax_e.axhline(5, color="r", lw=0.8, ls="--")
        lim = st["diameters"][name]["range_rho"]
        for a in (ax, ax_e):
            a.axvspan(-1, -lim, color="0.9")
            a.axvspan(lim, 1, color="0.9")
            a.set_xlim(-1, 1)
            a.grid(alpha=0.3)
        ax.set_ylim(-8, 2)
        ax_e.set_ylim(0, 20)
        ax_e.set_xlabel("y / R (loaded diameter)" if name == "loaded" else "x / R (unloaded diameter)")
        e = st["diameters"][name]
        ax.set_title(f"{name} diameter: max error {100 * e['max_error_sigma_xx']:.1f} % (xx), "
                     f"{100 * e['max_error_sigma_yy']:.1f} % (yy)", fontsize=9)
    axs[0, 0].set_ylabel(r"$\sigma / \sigma_0$,  $\sigma_0 = 2P/(\pi D t)$")
    axs[1, 0].set_ylabel("error (%)")
    axs[0, 0].legend(fontsize=7, loc="lower center")
    axs[1, 1].legend(fontsize=7, loc="upper center")
    fig.suptitle(f"Stresses before cracking, P = {st['load_N'] / 1e3:.0f} k{force_unit.replace('_per_', '/')} "
                 f"(t = {st['time_s'] * 1e3:.2f} ms), contact half-width {1e3 * np.mean(st['contact_half_width_measured_m']):.2f} "
                 f"mm (measured)\ndots: single triangles on the diameter; shaded: within 0.2 R of the plates / 0.1 R of "
                 f"the rim", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)



def draw_state(ax, f: dp.Fields, disc: np.ndarray, seg: dict, title: str, scale_stress: float,
               broken_by: float | None = None, softening: dict | None = None) -> None:
    """sigma_xx of frame f with the broken joints of seg (those broken by broken_by if
    given) in black and the softening joints of softening (damage > 0) in orange."""
    from matplotlib.collections import PolyCollection

    polys = f.x[f.tri]
    sxx = f.stress[:, 0]
    pc = PolyCollection(polys[disc], array=sxx[disc] / 1e6, cmap="coolwarm", edgecolors="none")
    pc.set_clim(-scale_stress / 1e6, scale_stress / 1e6)
    ax.add_collection(pc)
    others = ~disc
    ax.add_collection(PolyCollection(polys[others], facecolors="0.6", edgecolors="0.3", linewidths=0.3))
    broken = seg["state"] == 1
    if broken_by is not None and "time_broken" in seg:
        broken &= seg["time_broken"] <= broken_by
    if softening is not None:
        soft = (softening["damage"] > 0) & (softening["state"] != 1)
        ax.add_collection(LineCollection(np.stack([softening["a"][soft], softening["b"][soft]], axis=1),
                                         colors="darkorange", linewidths=1.2))
    lines = np.stack([seg["a"][broken], seg["b"][broken]], axis=1)
    ax.add_collection(LineCollection(lines, colors="k", linewidths=1.6))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return pc


def print_stress(st: dict) -> None:
    print(f"stress check       t = {st['time_s']:.4g} s, P = {st['load_N']:.4g}, contact half-width measured "
          f"{[round(1e3 * b, 3) for b in st['contact_half_width_measured_m']]} mm "
          f"(Hertz {1e3 * st['contact_half_width_hertz_m']:.3f} mm)")
    for name, c in st["diameters"].items():
        print(f"stress {name:<9}   max error xx {100 * c['max_error_sigma_xx']:.2f} %, yy {100 * c['max_error_sigma_yy']:.2f} % "
              f"(worst at {c['worst_rho']:+.3f}; within 0.7: {100 * c['max_error_sigma_xx_within_0.7']:.2f} %, "
              f"{100 * c['max_error_sigma_yy_within_0.7']:.2f} %; single triangles "
              f"{100 * c['single_triangles']['max_error_sigma_xx']:.1f} %, {100 * c['single_triangles']['max_error_sigma_yy']:.1f} %)")
    print(f"  {'PASS' if st['passed'] else 'FAIL'}  stresses within 5 %")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="output folder of dsdem run")
    ap.add_argument("--scenario", help="scenario file (default: the one named in OUT/summary.json)")
    ap.add_argument("--disc", default="disc", help="surface group of the disc")
    ap.add_argument("--plate", default="top_plate", help="surface group of the moving plate")
    ap.add_argument("--bottom-plate", default="bottom_plate", help="surface group of the fixed plate")
    ap.add_argument("--check-time", type=float, help="stress check at the frame nearest this time (s) instead of "
                    "the frame nearest 50 %% of the peak load")
    ap.add_argument("--stress-only", action="store_true",
                    help="only the stress check (runs stopped before the peak: scenario_stress.yaml); at --check-time "
                         "or the last frame; writes OUT/validation_stress.json and plots/stress_diameters.png")
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
    disc0 = disc_mask(f0)
    # Disc geometry from the mesh: centre and radius of the discrete zone.
    pts_disc = f0.X[np.unique(f0.tri[disc0])]
    centre = 0.5 * (pts_disc.min(axis=0) + pts_disc.max(axis=0))
    R = 0.5 * (pts_disc[:, 1].max() - pts_disc[:, 1].min())
    D = 2 * R
    scale = math.pi * D * t / 2  # P = scale * sigma_t

    # Plate displacement from the prescribed velocity history: integrate the plate's
    # velocity = the frames' displacement of the plate nodes; use the history time and
    # the frames to build u(t) (frames are exact, interpolate in between).
    plate_nodes = np.unique(f0.tri[(~disc0) & (f0.centroid0[:, 1] > centre[1])])
    u_frames = []
    for tf, path in frames:
        import meshio

        m = meshio.read(path)
        u_frames.append(-m.point_data["displacement_m"][plate_nodes, 1].mean())
    u_frames = np.array(u_frames)
    t_frames = np.array([tf for tf, _ in frames])
    u_plate = np.interp(time, t_frames, u_frames)

    if args.stress_only:
        tf, path = min(frames, key=lambda fr: abs(fr[0] - (frames[-1][0] if args.check_time is None else args.check_time)))
        st = stress_check(dp.Fields(path), centre, R, float(np.interp(tf, time, P)), t, E, nu)
        st = {"time_s": tf, "elements": summary.get("elements"), "wall_time_s": summary.get("wall_time_s"), **st}
        dp.write_json(os.path.join(out, "validation_stress.json"), {k: v for k, v in st.items() if k != "_curves"})
        if not args.no_plots:
            os.makedirs(os.path.join(out, "plots"), exist_ok=True)
            plot_stress(os.path.join(out, "plots", "stress_diameters.png"), st, force_unit)
        print_stress(st)
        return 0 if st["passed"] else 1

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
        pieces_end = (f_end.pieces(disc_mask(f_end)) / disc_area).tolist()

    # Stress check before cracking: frame nearest 50 % of the peak (on the rising branch),
    # or the frame nearest --check-time.
    rising = [(tf, p) for tf, p in frames if tf <= time[i_peak]]
    if args.check_time is not None:
        rising = frames
    P_frames = np.interp([tf for tf, _ in rising], time, P)
    if args.check_time is not None:
        k = int(np.argmin(np.abs(np.array([tf for tf, _ in rising]) - args.check_time)))
    else:
        k = int(np.argmin(np.abs(P_frames - 0.5 * P_peak)))
    t_check, path_check = rising[k]
    P_mean = float(P_frames[k])
    st = stress_check(dp.Fields(path_check), centre, R, P_mean, t, E, nu)
    st = {"time_s": t_check, **st}

    stress_ok = st["passed"]
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
        "stress_check": {k: v for k, v in st.items() if k != "_curves"},
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
    dp.merge_summary(out, {k: result[k] for k in (
        "peak_load_N", "tensile_strength_Pa", "input_tensile_strength_Pa", "relative_error",
        "t_first_crack_s", "first_crack_position_m", "t_through_crack_s")})

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

        plot_stress(os.path.join(plots, "stress_diameters.png"), st, force_unit)

        # Crack snapshots. The crack runs through the disc within tens of microseconds,
        # less than the frame interval: the first-crack picture is the last frame before
        # the first joint broke (its sigma_xx, and its softening joints in orange) with
        # the joints broken by then (time_broken from the next crack frame) in black.
        snaps = []
        if first is not None:
            fb = dp.frame_before(frames, first["time_s"]) or frames[0]
            fa = dp.frame_after(frames, first["time_s"]) or frames[-1]
            snaps.append(("cracks_first.png", fb, dp.frame_nearest(crack_frames, fa[0])[1], first["time_s"] + 1e-6,
                          dp.frame_nearest(crack_frames, fb[0])[1],
                          f"first crack: joint broken at t = {first['time_s'] * 1e3:.2f} ms (black);\n"
                          f"sigma_xx and softening joints (orange) at t = {fb[0] * 1e3:.2f} ms"))
        if frame_through is not None:
            snaps.append(("cracks_through.png", frame_through, dp.frame_nearest(crack_frames, frame_through[0])[1],
                          None, None,
                          f"through crack at t = {t_through * 1e3:.2f} ms; frame t = {frame_through[0] * 1e3:.2f} ms"))
        for fname, (tf, path), seg_path, broken_by, soft_path, title in snaps:
            f = dp.Fields(path)
            seg = dp.read_segments(seg_path)
            soft = dp.read_segments(soft_path) if soft_path else None
            fig, ax = plt.subplots(figsize=(5.2, 5.6))
            pc = draw_state(ax, f, disc_mask(f), seg, title, 3 * ft, broken_by, soft)
            fig.colorbar(pc, ax=ax, shrink=0.7, label=r"$\sigma_{xx}$ (MPa)")
            fig.tight_layout()
            fig.savefig(os.path.join(plots, fname), dpi=110)
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
    print_stress(st)
    for k, v in result["acceptance"].items():
        print(f"  {'PASS' if v else 'FAIL'}  {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
