#!/usr/bin/python3
"""Dr2 with the reservoir as moving water against the dry runs (docs/dr2.md §10).

Usage: table.py OUT_ROOT [MODE ...]
Reads OUT_ROOT/<mode>_dry and OUT_ROOT/<mode>_wet (each a dsdem run post-processed by
scripts/dr2_postprocess.py: summary.json with its dr2 keys, history.csv, wall_seconds) and
writes OUT_ROOT/table.md (the wave, the run-up on the far bank, the force on the intake, the
deposit wet against dry, Heller & Hager beside the computed wave) and OUT_ROOT/gauges.png (the
free surface at the gauges against time, each mode).
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NAMES = {"shear_sliding": "shear sliding", "local_collapse": "local collapse", "slip_j1": "slip J1"}


def load(path):
    with open(os.path.join(path, "summary.json")) as f:
        s = json.load(f)
    wall = None
    p = os.path.join(path, "wall_seconds")
    if os.path.exists(p):
        wall = float(open(p).read())
    return s, wall


def history(path):
    with open(os.path.join(path, "history.csv")) as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    return rows


def fmt(v, spec="{:.1f}", none="-"):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return none
    return spec.format(v)


def row(mode, root):
    dry, dry_wall = load(os.path.join(root, mode + "_dry"))
    wet, wet_wall = load(os.path.join(root, mode + "_wet"))
    m = wet["moving_water"]
    hh = wet.get("heller_hager", {})
    amp = m["max_wave_amplitude"]
    runup = m["runup"].get("left_bank", {})
    force = m["force_on_curves"].get("intake", {})
    periods = [p for p in m.get("wave_period_s", {}).values() if p is not None]
    level = wet["heller_hager"]["still_level_m"] if "heller_hager" in wet else 837.0
    rows = history(os.path.join(root, mode + "_wet"))
    gauges = {}
    for k in rows[0]:
        if not k.endswith("_eta_m"):
            continue
        series = [(float(r["time_s"]), float(r[k])) for r in rows if r[k] not in ("", "nan", "NaN")]
        top = max(series, key=lambda p: p[1]) if series else (None, None)
        end = float(rows[-1][k]) if rows[-1][k] not in ("", "nan", "NaN") else None
        gauges[k[:-6]] = {"max": top[1], "t": top[0], "end": end}
    return {
        "mode": NAMES.get(mode, mode),
        "gauges": gauges,
        "particles": m["particles"],
        "amp": amp.get("amplitude_m"), "amp_x": amp.get("x_m"), "amp_t": amp.get("time_s"),
        "impact_t": hh.get("impact_time_s"),
        "hh_amp": hh.get("amplitude_m"), "hh_inside": hh.get("inside_validity"), "hh_out": hh.get("outside_validity", []),
        "runup": (runup.get("elevation_m") - level) if runup.get("elevation_m") is not None else None,
        "runup_t": runup.get("time_s"),
        "period": sum(periods) / len(periods) if periods else None,
        "periods": m.get("wave_period_s", {}),
        "force": force.get("max_force_N_per_m"), "pressure": force.get("peak_pressure_Pa"),
        "ratio": m.get("energy_handed_to_water_ratio"),
        "escaped": m.get("escaped_particles"), "above": m.get("above_freeboard_particles"),
        "dry_disp": dry.get("mean_max_displacement_m"), "wet_disp": wet.get("mean_max_displacement_m"),
        "dry_block": dry.get("river_blocked_time_s"), "wet_block": wet.get("river_blocked_time_s"),
        "dry_intake": dry.get("intake_debris_height_m"), "wet_intake": wet.get("intake_debris_height_m"),
        "dry_channel": dry.get("deposit_area_in_channel_m2"), "wet_channel": wet.get("deposit_area_in_channel_m2"),
        "dry_wall": dry_wall, "wet_wall": wet_wall,
        "dry_balance": dry.get("energy_balance_error"), "wet_balance": wet.get("energy_balance_error"),
    }


def write_table(rows, out):
    lines = ["| mode | max amplitude (m) | where, when | H&H a_M (m) | run-up, far bank (m) | mean period (s) | "
             "intake: force (MN/m), peak pressure (MPa) | energy to water | particles (escaped, above freeboard) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        where = f"x = {fmt(r['amp_x'], '{:.0f}')} m, t = {fmt(r['amp_t'])} s"
        if r["impact_t"] is not None:
            where += f" (entry {r['impact_t']:.1f} s)"
        hh = fmt(r["hh_amp"])
        if r["hh_amp"] is not None and not r["hh_inside"]:
            hh += " (outside: " + ", ".join(o["parameter"] for o in r["hh_out"]) + ")"
        force = f"{fmt(r['force'] and r['force'] / 1e6, '{:.2f}')}, {fmt(r['pressure'] and r['pressure'] / 1e6, '{:.2f}')}"
        lines.append(f"| {r['mode']} | {fmt(r['amp'])} | {where} | {hh} | {fmt(r['runup'])} | {fmt(r['period'])} | "
                     f"{force} | {fmt(r['ratio'], '{:.3f}')} | {r['particles']} ({r['escaped']}, {r['above']}) |")
    lines += ["", "| mode | mean max displacement dry / wet (m) | river blocked at dry / wet (s) | "
                  "debris over the intake dry / wet (m) | deposit in the channel dry / wet (m2) | "
                  "wall dry / wet (s, one thread) | balance error dry / wet |",
              "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['mode']} | {fmt(r['dry_disp'], '{:.0f}')} / {fmt(r['wet_disp'], '{:.0f}')} | "
                     f"{fmt(r['dry_block'])} / {fmt(r['wet_block'])} | {fmt(r['dry_intake'], '{:.0f}')} / "
                     f"{fmt(r['wet_intake'], '{:.0f}')} | {fmt(r['dry_channel'], '{:.0f}')} / "
                     f"{fmt(r['wet_channel'], '{:.0f}')} | {fmt(r['dry_wall'], '{:.0f}')} / {fmt(r['wet_wall'], '{:.0f}')} | "
                     f"{fmt(r['dry_balance'], '{:.1e}')} / {fmt(r['wet_balance'], '{:.1e}')} |")
    lines += ["", "| mode | gauge | x (m) | highest surface above 837 m (m) | when (s) | at the end (m) | mean crest period (s) |",
              "|---|---|---|---|---|---|---|"]
    for r in rows:
        for g, v in r["gauges"].items():
            lines.append(f"| {r['mode']} | {g} | {g[1:]} | {fmt(v['max'])} | {fmt(v['t'])} | {fmt(v['end'])} | "
                         f"{fmt(r['periods'].get(g))} |")
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def plot(modes, root):
    fig, axes = plt.subplots(1, len(modes), figsize=(5.2 * len(modes), 3.6), squeeze=False)
    for ax, mode in zip(axes[0], modes):
        path = os.path.join(root, mode + "_wet")
        rows = history(path)
        t = [float(r["time_s"]) for r in rows]
        gauges = [k for k in rows[0] if k.endswith("_eta_m")]
        for g in gauges:
            ax.plot(t, [float(r[g]) if r[g] not in ("", "nan") else math.nan for r in rows], lw=1,
                    label=g[:-6] + " m")
        if "left_bank_runup_m" in rows[0]:
            ax.plot(t, [float(r["left_bank_runup_m"]) - 837.0 for r in rows], "k--", lw=1, label="run-up, far bank")
        s, _ = load(path)
        hh = s.get("heller_hager", {})
        if hh.get("slide_entered_water"):
            ax.axvline(hh["impact_time_s"], color="grey", lw=0.8, ls=":")
            if hh.get("amplitude_m") is not None:
                ax.axhline(hh["amplitude_m"], color="red", lw=0.8, ls=":", label="H&H a_M")
        ax.set_title(NAMES.get(mode, mode))
        ax.set_xlabel("t (s)")
        ax.set_ylabel("water surface above 837 m (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(root, "gauges.png"), dpi=110)


def main():
    root = sys.argv[1]
    modes = sys.argv[2:] or ["shear_sliding", "local_collapse", "slip_j1"]
    modes = [m for m in modes if os.path.exists(os.path.join(root, m + "_wet", "summary.json"))]
    write_table([row(m, root) for m in modes], root)
    plot(modes, root)


if __name__ == "__main__":
    main()
