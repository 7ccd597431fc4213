#!/usr/bin/python3
"""Post-processing of the four-point impact beam (examples/beam_impact, docs/validation.md §2).

    python3 scripts/validate_beam.py OUT [--scenario examples/beam_impact/scenario.yaml]

Reads OUT/history.csv, OUT/cracks.csv, OUT/fields/*.vtu and OUT/cracks/*.vtu of
`dsdem run`, writes OUT/validation.json and PNG plots in OUT/plots/:

  midspan_deflection.png   mid-span deflection (gauge 'midspan' at the bottom face),
                           impactor velocity, broken joints and fragments against time
  cracks_sequence.png      the beam at a few instants, broken joints coloured by the
                           time they broke
  crack_map.png            every broken joint at its breaking position, coloured by time

Definitions (docs/validation.md):
  mid-span deflection  -u_y of the gauge 'midspan' (bottom face at x = 0)
  crushing             broken joints within two head radii of a head's contact point
                       (local failure under the steel heads); kept apart from the cracks
  first crack          first broken joint that is not crushing
  pieces               fragments of the beam (fragment field of the last frame) with at
                       least 1 % of the beam's area; smaller ones are debris
  dominant mode        share of the opening in the failure criterion of a broken joint
                       (en^2 / (en^2 + es^2) at failure); >= 0.5: tension-dominated. The
                       solver's own label is 'mixed' as soon as the slip passed its
                       (tiny) elastic limit, which on inclined edges is nearly always.
  cracks               broken joints (crushing apart) linked by single linkage: break
                       positions within two element sizes of each other belong to one
                       crack; each crack is reported with the time, position and mode of
                       its first joint, its x extent, where it started (bottom / top
                       face: first joint within 0.2 H of it), the height it reached and
                       the rank correlation of height with time (grew upward: from the
                       bottom with correlation > 0.5)
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
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402


def group_cracks(cracks: list[dict], link: float) -> list[list[dict]]:
    """Cracks: broken joints linked by single linkage in the plane (break positions
    within `link` of each other), each in order of breaking; cracks in order of their
    first joint."""
    n = len(cracks)
    parent = list(range(n))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    xy = np.array([[c["x_m"], c["y_m"]] for c in cracks]) if n else np.zeros((0, 2))
    for i in range(n):
        d = np.hypot(xy[i + 1:, 0] - xy[i, 0], xy[i + 1:, 1] - xy[i, 1])
        for j in np.nonzero(d <= link)[0]:
            a, b = root(i), root(i + 1 + int(j))
            if a != b:
                parent[max(a, b)] = min(a, b)
    groups: dict[int, list[dict]] = {}
    for i in range(n):
        groups.setdefault(root(i), []).append(cracks[i])
    out = [sorted(g, key=lambda c: c["time_s"]) for g in groups.values()]
    out.sort(key=lambda g: g[0]["time_s"])
    return out


def rank_correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman rank correlation (no ties handling needed for times and heights)."""
    if len(a) < 2:
        return 0.0
    ra = np.argsort(np.argsort(a)).astype(float)
    rb = np.argsort(np.argsort(b)).astype(float)
    if ra.std() == 0 or rb.std() == 0:
        return 0.0
    return float(np.corrcoef(ra, rb)[0, 1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="output folder of dsdem run")
    ap.add_argument("--scenario", help="scenario file (default: the one named in OUT/summary.json)")
    ap.add_argument("--beam", default="beam", help="surface group of the beam")
    ap.add_argument("--gauge", default="midspan", help="gauge at the bottom face at mid-span")
    ap.add_argument("--head-spacing", type=float, default=0.203, help="distance between the impactor heads, m")
    ap.add_argument("--head-radius", type=float, default=0.025, help="radius of the impactor heads, m")
    ap.add_argument("--span", type=float, default=1.422, help="distance between the supports, m")
    ap.add_argument("--element-size", type=float, default=None,
                    help="link distance / 2 for grouping joints into cracks (default: mesh.element_size)")
    ap.add_argument("--no-plots", action="store_true")
    args = ap.parse_args()
    out = args.out

    sc = dp.load_scenario(out, args.scenario)
    if args.element_size is None:
        args.element_size = float(sc["mesh"]["element_size"])
    summary = dp.read_summary(out)
    hist = dp.read_history(out)
    time = hist["time_s"]
    frames = dp.read_pvd(out, "fields")
    crack_frames = dp.read_pvd(out, "cracks")
    f0 = dp.Fields(frames[0][1])
    beam0 = f0.zone == 0
    Xb = f0.X[np.unique(f0.tri[beam0])]
    x_min, x_max = Xb[:, 0].min(), Xb[:, 0].max()
    y_bot, y_top = Xb[:, 1].min(), Xb[:, 1].max()
    L, H = x_max - x_min, y_top - y_bot
    xc = 0.5 * (x_min + x_max)
    beam_area = f0.area0[beam0].sum()

    defl = -dp.column(hist, f"{args.gauge}_displacement_y")
    i_max = int(np.argmax(defl))
    all_cracks = dp.read_cracks(out)
    # Crushing under the heads: joints that broke within two head radii of a head's
    # contact point (the steel heads load the concrete over about a millimetre: the
    # contact pressure passes the compressive strength at well under 1 kN per head,
    # long before the beam bends enough to crack). Reported apart from the cracks.
    heads = args.head_spacing / 2
    def near_head(c):
        return min(math.hypot(c["x_m"] - xc - s * heads, c["y_m"] - y_top) for s in (-1, 1)) <= 2 * args.head_radius
    crushing = [c for c in all_cracks if near_head(c)]
    cracks = [c for c in all_cracks if not near_head(c)]
    groups = group_cracks(cracks, 2.0 * args.element_size)

    # Pieces at the end.
    f_end = dp.Fields(frames[-1][1])
    pieces = f_end.pieces(f_end.zone == 0) / beam_area
    n_pieces = int(np.sum(pieces >= 0.01))
    # Pieces over time (frames), for the sequence.
    piece_history = []
    for tf, path in frames:
        f = dp.Fields(path)
        p = f.pieces(f.zone == 0) / beam_area
        piece_history.append((tf, int(np.sum(p >= 0.01))))
    t_first_split = next((tf for tf, n in piece_history if n >= 2), None)

    # Dominant mode of each broken joint (share of the opening in the failure criterion
    # at failure, from the last crack frame).
    jd = dict(sc.get("joints", {}).get("default", {}))
    share = {}
    if cracks and crack_frames:
        seg_last = dp.read_segments(crack_frames[-1][1])
        ids = [c["joint"] for c in all_cracks]
        sh = dp.failure_shares(seg_last, ids, float(jd["ft"]), float(jd["GI"]), float(jd["c"]), float(jd["GII"]))
        share = dict(zip(ids, sh))

    crack_list = []
    for g in groups:
        first = g[0]
        ys = np.array([c["y_m"] - y_bot for c in g])
        ts = np.array([c["time_s"] for c in g])
        modes = {}
        for c in g:
            modes[c["mode"]] = modes.get(c["mode"], 0) + 1
        trend = rank_correlation(ts, ys)
        origin = "bottom" if ys[0] <= 0.2 * H else ("top" if ys[0] >= 0.8 * H else "inside")
        upward = bool(len(g) >= 3 and origin == "bottom" and trend > 0.5)
        downward = bool(len(g) >= 3 and origin == "top" and trend < -0.5)
        crack_list.append({
            "time_s": first["time_s"],
            "x_m": first["x_m"] - xc,
            "y_m": first["y_m"] - y_bot,
            "mode": first["mode"],
            "joints": len(g),
            "x_range_m": [min(c["x_m"] for c in g) - xc, max(c["x_m"] for c in g) - xc],
            "height_reached_m": float(ys.max()),
            "height_reached_over_H": float(ys.max() / H),
            "y_range_over_H": [float(ys.min() / H), float(ys.max() / H)],
            "last_time_s": float(ts.max()),
            "modes": modes,
            "tension_dominated_fraction": float(np.mean([share.get(c["joint"], 0.5) >= 0.5 for c in g])),
            "origin": origin,
            "height_time_rank_correlation": trend,
            "grew_upward_from_bottom": upward,
            "grew_downward_from_top": downward,
        })
    # Keep the cracks that matter (>= 3 joints, i.e. more than a chipped corner).
    major = [c for c in crack_list if c["joints"] >= 3]

    first = cracks[0] if cracks else None
    span = args.span / 2
    first_under_impact = bool(first is not None and abs(first["x_m"] - xc) <= heads + 0.05 and
                              (first["y_m"] - y_bot) <= 0.2 * H)
    # Quarter points: of the beam |x| = L/4 = 0.4 m, of the span 0.356 m; window 0.25-0.55 m.
    quarter = [c for c in major if 0.25 <= abs(c["x_m"]) <= 0.55]
    central = [c for c in major if abs(c["x_m"]) <= heads + 0.05]

    wall = summary.get("wall_time_s")
    result = {
        "case": "beam_impact",
        "scenario": summary.get("scenario"),
        "beam_length_m": L,
        "beam_depth_m": H,
        "elements": summary.get("elements"),
        "joints": summary.get("joints"),
        "dt_s": summary.get("dt_s"),
        "end_time_s": summary.get("end_time_s"),
        "wall_time_s": wall,
        "max_midspan_deflection_m": float(defl[i_max]),
        "time_of_max_midspan_deflection_s": float(time[i_max]),
        "midspan_deflection_at_first_split_m": None if t_first_split is None else float(np.interp(t_first_split, time, defl)),
        "t_first_split_s": t_first_split,
        "fragments": n_pieces,
        "fragments_all": int(len(pieces)),
        "piece_area_fractions": [round(float(p), 4) for p in pieces[:8]],
        "broken_joints": summary.get("broken_joints"),
        "crushing_under_heads": {
            "joints": len(crushing),
            "first_time_s": crushing[0]["time_s"] if crushing else None,
            "tension_dominated_fraction": float(np.mean([share.get(c["joint"], 0.5) >= 0.5 for c in crushing])) if crushing else None,
        },
        "first_crack": None if first is None else {
            "time_s": first["time_s"], "x_m": first["x_m"] - xc, "y_m": first["y_m"] - y_bot, "mode": first["mode"]},
        "cracks": major,
        "energy_balance_error": summary.get("energy_balance_error"),
        "expected": {
            "first_crack_on_bottom_face_under_impact": first_under_impact,
            "first_crack_grows_upward": bool(major and major[0]["grew_upward_from_bottom"]),
            "cracks_near_quarter_points": len(quarter) > 0,
            "pieces_4_to_6": 4 <= n_pieces <= 6,
        },
    }
    plots = os.path.join(out, "plots")
    os.makedirs(plots, exist_ok=True)
    dp.write_json(os.path.join(out, "validation.json"), result)
    # The runner's 'fragments' counts every body (impactor, supports, debris); the case's
    # 'fragments' is the beam's pieces (>= 1 % of its area): the runner's number is kept
    # as 'fragments_all_bodies'.
    dp.merge_summary(out, {
        "max_midspan_deflection_m": result["max_midspan_deflection_m"],
        "fragments": n_pieces,
        # mode: the dominant mode of the crack's joints (share of the opening in the
        # failure criterion, see the docstring); the solver's label of its first joint
        # is kept as solver_mode. x from mid-span, y from the bottom face.
        "crack_sequence": [{"time_s": c["time_s"], "x_m": c["x_m"], "y_m": c["y_m"],
                            "mode": "tension" if c["tension_dominated_fraction"] >= 0.5 else "shear",
                            "solver_mode": c["mode"], "joints": c["joints"], "origin": c["origin"]} for c in major],
    }, renamed={"fragments": "fragments_all_bodies"})

    if not args.no_plots:
        fig = plt.figure(figsize=(7, 10))
        gs = fig.add_gridspec(4, 1)
        ax_zoom = fig.add_subplot(gs[0])
        axs = [fig.add_subplot(gs[k]) for k in (1, 2, 3)]
        for ax in axs[1:]:
            ax.sharex(axs[0])
        t_zoom = 3.0 * (first["time_s"] if first else time[-1] / 4)
        zm = time <= t_zoom
        ax_zoom.plot(time[zm] * 1e3, defl[zm] * 1e3, lw=1.2)
        for c in major[:12]:
            ax_zoom.axvline(c["time_s"] * 1e3, color="0.7", lw=0.6)
        if crushing:
            ax_zoom.axvline(crushing[0]["time_s"] * 1e3, color="r", lw=0.8, ls=":", label="crushing under a head")
        if first:
            ax_zoom.axvline(first["time_s"] * 1e3, color="k", lw=0.8, label="first crack")
        ax_zoom.legend(fontsize=7)
        ax_zoom.set_ylabel("deflection (mm)")
        ax_zoom.set_xlabel("time (ms)")
        ax_zoom.grid(alpha=0.3)
        ax_zoom.set_title(f"Mid-span deflection, first {t_zoom * 1e3:.1f} ms (grey: crack onsets)", fontsize=9)
        axs[0].plot(time * 1e3, defl * 1e3, lw=1.2)
        axs[0].set_ylabel("mid-span deflection (mm)")
        if t_first_split is not None:
            for ax in axs:
                ax.axvline(t_first_split * 1e3, color="C3", lw=0.8, ls="--")
        for c in major[:12]:
            axs[0].axvline(c["time_s"] * 1e3, color="0.7", lw=0.6)
        axs[0].set_title("Whole run (red: beam first in two pieces, to the frame interval)", fontsize=9)
        gname = next((n for n in hist if n.startswith("impactor_velocity_y")), None)
        if gname:
            axs[1].plot(time * 1e3, hist[gname], lw=1.2, color="C1")
            axs[1].set_ylabel("impactor velocity (m/s)")
        else:
            axs[1].plot(time * 1e3, dp.column(hist, "kinetic"), lw=1.2, color="C1")
            axs[1].set_ylabel("kinetic energy")
        axs[2].plot(time * 1e3, hist["broken_joints"], lw=1.2, color="C2", label="broken joints")
        axs[2].set_ylabel("broken joints")
        ax2 = axs[2].twinx()
        n_other = int(hist["fragments"][0]) - 1  # bodies other than the beam (impactor, supports)
        ax2.step(time * 1e3, hist["fragments"] - n_other, where="post", lw=1, color="C4")
        ax2.set_ylabel("beam fragments (all sizes)", color="C4")
        axs[2].set_xlabel("time (ms)")
        for ax in axs:
            ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(plots, "midspan_deflection.png"), dpi=130)
        plt.close(fig)

        # Snapshots: first crack, a few along the sequence, the end.
        t_end = time[-1]
        t_first = first["time_s"] if first else frames[0][0]
        wanted = [t_first, t_first + 0.25 * (t_end - t_first) * 0.2, t_first_split or t_end,
                  0.5 * (t_end + (t_first_split or t_first)), t_end]
        snaps = []
        for tw in wanted:
            fr = dp.frame_after(frames, tw) or frames[-1]
            if fr not in snaps:
                snaps.append(fr)
        fig, axs = plt.subplots(len(snaps), 1, figsize=(9, 2.0 * len(snaps) + 0.6), constrained_layout=True)
        axs = np.atleast_1d(axs)
        t_lo = cracks[0]["time_s"] if cracks else 0.0
        t_hi = max(cracks[-1]["time_s"] if cracks else t_end, t_lo + 1e-6)
        for ax, (tf, path) in zip(axs, snaps):
            f = dp.Fields(path)
            polys = f.x[f.tri]
            beam = f.zone == 0
            ax.add_collection(PolyCollection(polys[beam], facecolors="#d9d4c7", edgecolors="none"))
            ax.add_collection(PolyCollection(polys[~beam], facecolors="0.55", edgecolors="none"))
            seg = dp.read_segments(dp.frame_nearest(crack_frames, tf)[1])
            br = seg["state"] == 1
            lc = LineCollection(np.stack([seg["a"][br], seg["b"][br]], axis=1), array=seg["time_broken"][br] * 1e3,
                                cmap="viridis", linewidths=1.4)
            lc.set_clim(t_lo * 1e3, t_hi * 1e3)
            ax.add_collection(lc)
            ax.set_aspect("equal")
            ax.set_xlim(x_min - 0.02, x_max + 0.02)
            ax.set_ylim(y_bot - 0.15, y_top + 0.25)
            npc = next((n for t_, n in piece_history if abs(t_ - tf) < 1e-12), None)
            ax.set_title(f"t = {tf * 1e3:.2f} ms: {int(br.sum())} broken joints, {npc} pieces", fontsize=8)
            ax.tick_params(labelsize=7)
        fig.colorbar(lc, ax=list(axs), shrink=0.5, label="time broken (ms)")
        fig.savefig(os.path.join(plots, "cracks_sequence.png"), dpi=100)
        plt.close(fig)

        # Crack map in the reference configuration (break positions) coloured by time.
        fig, ax = plt.subplots(figsize=(9, 2.6))
        ax.add_patch(plt.Rectangle((x_min - xc, 0), L, H, fc="none", ec="k", lw=0.8))
        if crushing:
            ax.scatter([c["x_m"] - xc for c in crushing], [c["y_m"] - y_bot for c in crushing], s=10, marker="x",
                       color="r", lw=0.8, label="crushing under the heads")
            ax.legend(fontsize=7, loc="lower right", bbox_to_anchor=(1.0, 1.02), borderaxespad=0)
        if cracks:
            xs = np.array([c["x_m"] - xc for c in cracks])
            ys = np.array([c["y_m"] - y_bot for c in cracks])
            ts = np.array([c["time_s"] for c in cracks]) * 1e3
            sca = ax.scatter(xs, ys, c=ts, s=6, cmap="viridis")
            fig.colorbar(sca, ax=ax, label="time broken (ms)")
        for xs_ in (-span, span):
            ax.plot([xs_], [0], "k^", ms=7)
        for xh in (-heads, heads):
            ax.plot([xh], [H], "rv", ms=7)
        ax.set_aspect("equal")
        ax.set_xlim(-L / 2 - 0.02, L / 2 + 0.02)
        ax.set_ylim(-0.05, H + 0.05)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title("Where and when joints broke\n(break position; the beam may have moved by then)", fontsize=9, loc="left")
        fig.tight_layout()
        fig.savefig(os.path.join(plots, "crack_map.png"), dpi=130)
        plt.close(fig)

    print(f"max mid-span deflection  {1e3 * defl[i_max]:.2f} mm at t = {1e3 * time[i_max]:.2f} ms")
    print(f"pieces                   {n_pieces} (>= 1 % of the beam), {len(pieces)} in all; areas {result['piece_area_fractions']}")
    print(f"first split              t = {t_first_split}")
    if crushing:
        print(f"crushing under heads     {len(crushing)} joints, first at t = {1e3 * crushing[0]['time_s']:.3f} ms")
    if first:
        print(f"first crack              t = {1e3 * first['time_s']:.3f} ms at x = {first['x_m'] - xc:+.3f} m, "
              f"y = {first['y_m'] - y_bot:.3f} m ({first['mode']})")
    for c in major:
        print(f"  crack t = {1e3 * c['time_s']:7.3f} ms  x = {c['x_m']:+.3f} m  y = {c['y_m']:.3f} m  {c['mode']:<8}"
              f" joints {c['joints']:4d} ({100 * c['tension_dominated_fraction']:.0f} % tension-dominated)"
              f"  from the {c['origin']:<6} reached {c['height_reached_over_H']:.2f} H, height-time rank corr."
              f" {c['height_time_rank_correlation']:+.2f}")
    for k, v in result["expected"].items():
        print(f"  {'YES' if v else 'NO '}  {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
