#!/usr/bin/env python3
"""Granular slide into still water: dsdem's impulse wave against Heller & Hager (2010).

Usage: compare.py OUT/A OUT/B OUT/C [-o DIR]
Reads each run's summary.json and history.csv and writes DIR/results.md (the tables) and
DIR/impulse_wave.png (the gauges against time; measured against Heller & Hager amplitude
with their +/-30 % band).

What is compared: summary.json heller_hager.amplitude_m, H&H's a_M = (4/9) P^(4/5) h from the
slide the run measured where it entered the water (its speed, thickness and mass, the bank's
angle), against max_wave_amplitude_m: the highest free surface above the still level (the
settled water's mean surface just before the slide entered, moving_water.still_level_m) over
water at least h/4 deep and beyond the slide's front, at any time. Beside it, the largest crest
at the free-surface gauges over the flat bed, from the same still level; and at each gauge the
primary wave (its first crest after the entry and the trough after it, summary.json
heller_hager.gauges) against Heller & Hager's 2D decay laws a(x) = 3/5 (P (x/h)^-1/3)^4/5 h and
H(x) = 3/4 (P (x/h)^-1/3)^4/5 h, which meet a_M and H_M at x/h = 3.08.
"""
import argparse
import csv
import json
import os

TOE_X = 2.0  # m: the foot of the 45-degree plane (flume.geo); the flat bed starts here


def gauge_positions():
    """Gauge x from impulse_wave.yaml (lines '- {name: gN, x: X}')."""
    here = os.path.dirname(os.path.abspath(__file__))
    xs = {}
    with open(os.path.join(here, "impulse_wave.yaml")) as f:
        for line in f:
            line = line.strip()
            if line.startswith("- {name: g"):
                name = line.split("name:")[1].split(",")[0].strip()
                xs[name] = float(line.split("x:")[1].split("}")[0])
    return xs


def read_case(path, xs):
    with open(os.path.join(path, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(path, "history.csv")) as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    hh, mw = s["heller_hager"], s["moving_water"]
    h, level, still = hh["depth_m"], hh["still_level_m"], mw["still_level_m"]
    gauges = sorted((k[:-6] for k in rows[0] if k.endswith("_eta_m")), key=lambda g: xs[g])
    t = [float(r["time_s"]) for r in rows]
    # The gauges' columns are above reservoir.level: from the still level as the amplitude.
    eta = {g: [float(r[g + "_eta_m"]) + level - still for r in rows] for g in gauges}
    wall, cpu = None, None
    for name in ("wall_seconds", "cpu_seconds"):
        p = os.path.join(path, name)
        if os.path.exists(p):
            with open(p) as f:
                v = float(f.read())
            wall, cpu = (v, cpu) if name == "wall_seconds" else (wall, v)
    x0 = hh["shoreline_m"][0]
    peak = mw["max_wave_amplitude"]
    flat = [g for g in gauges if xs[g] >= TOE_X]
    gmax, gname = max((max(eta[g]), g) for g in flat)
    return dict(name=os.path.basename(os.path.normpath(path)), h=h, dp=mw["spacing_m"], F=hh["froude"],
                S=hh["relative_thickness"], M=hh["relative_mass"], P=hh["impulse_product"],
                inside=hh["inside_validity"], aHH=hh["amplitude_m"], xM=hh["distance_of_max_height_m"],
                a=s["max_wave_amplitude_m"], ax=(peak["x_m"] - x0) / h, at=peak["time_s"] - hh["impact_time_s"],
                V=hh["slide_speed_mps"], s=hh["slide_thickness_m"], m=hh["slide_mass_kg_per_m"],
                timp=hh["impact_time_s"], g=gmax, gx=(xs[gname] - x0) / h, gname=gname, wall=wall, cpu=cpu, t=t, eta=eta,
                gauges=gauges, x0=x0, offset=(still - level) / h, escaped=mw["escaped_particles"],
                handed=mw.get("energy_handed_to_water_ratio"), runup=mw["runup"]["wall"]["elevation_m"],
                decay=hh.get("gauges", []))


def fmt(v, spec):
    """A number in `spec`, or '-' for a null (a wave not seen before the run ended)."""
    return format(v, spec) if isinstance(v, (int, float)) else "-"


def tables(cases):
    out = ["| case | h (m) | dp (m) | s/dp | V_s (m/s) | s (m) | m_s (kg/m) | F | S | M | P | inside validity "
           "| a_M H&H (m) | a_M dsdem (m) | at x/h, t - t_impact (s) | ratio |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        out.append(f"| {c['name']} | {c['h']:.2f} | {c['dp']:.4f} | {c['s'] / c['dp']:.1f} | {c['V']:.2f} | {c['s']:.3f} "
                   f"| {c['m']:.0f} | {c['F']:.2f} | {c['S']:.2f} | {c['M']:.2f} | {c['P']:.2f} "
                   f"| {'yes' if c['inside'] else 'no'} | {c['aHH']:.3f} | {c['a']:.3f} | {c['ax']:.2f}, {c['at']:.2f} "
                   f"| {c['a'] / c['aHH']:.2f} |")
    out += ["", "The largest crest at the free-surface gauges over the flat bed (x >= 2 m), from the same still level:",
            "", "| case | gauge | x/h from the shoreline | x_M/h H&H | crest (m) | ratio to a_M H&H |",
            "|---|---|---|---|---|---|"]
    for c in cases:
        out.append(f"| {c['name']} | {c['gname']} | {c['gx']:.1f} | {c['xM'] / c['h']:.1f} | {c['g']:.3f} "
                   f"| {c['g'] / c['aHH']:.2f} |")
    out += ["", "The primary wave at each gauge (its first crest after the entry, the trough after it) against "
            "Heller & Hager's decay laws at its distance x from the shoreline:", "",
            "| case | gauge | x/h | crest (m) | a(x) H&H (m) | ratio | crest to trough (m) | H(x) H&H (m) | ratio |",
            "|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        for g in c["decay"]:
            out.append(f"| {c['name']} | {g['name']} | {g['relative_distance']:.2f} | {fmt(g['crest_m'], '.3f')} "
                       f"| {g['heller_hager_crest_m']:.3f} | {fmt(g['crest_ratio'], '.2f')} | {fmt(g['height_m'], '.3f')} "
                       f"| {g['heller_hager_height_m']:.3f} | {fmt(g['height_ratio'], '.2f')} |")
    out += ["", "| case | wall / CPU time (s, one thread) | still level - reservoir.level (h) | particles escaped "
            "| slide energy handed to the water | highest water on the end wall (m) |", "|---|---|---|---|---|---|"]
    for c in cases:
        out.append(f"| {c['name']} | {fmt(c['wall'], '.0f')} / {fmt(c['cpu'], '.0f')} | {c['offset']:+.4f} | {c['escaped']} "
                   f"| {fmt(c['handed'], '.2f')} | {fmt(c['runup'], '.3f')} |")
    return out


def plot(cases, xs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(cases) + 1, figsize=(3.4 * (len(cases) + 1), 3.0))
    for ax, c in zip(axes, cases):
        for g in c["gauges"]:
            ax.plot([t - c["timp"] for t in c["t"]], [e / c["h"] for e in c["eta"][g]], lw=0.8,
                    label=f"x/h {(xs[g] - c['x0']) / c['h']:.1f}")
        ax.axhline(c["aHH"] / c["h"], color="k", ls="--", lw=0.8, label="a_M H&H")
        ax.set_xlim(-0.2, max(c["t"]) - c["timp"])
        ax.set_title(f"{c['name']}: F={c['F']:.2f} S={c['S']:.2f} M={c['M']:.2f}", fontsize=8)
        ax.set_xlabel("t - t_impact (s)", fontsize=8)
        ax.set_ylabel("eta / h", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=5, ncol=2)
    ax = axes[-1]
    top = 1.25 * max(max(c["a"], c["aHH"], c["g"]) / c["h"] for c in cases)
    ax.plot([0, top], [0, top], "k-", lw=0.8)
    ax.fill_between([0, top], [0, 0.7 * top], [0, 1.3 * top], color="0.85", label="+/-30 %")
    for c in cases:
        line, = ax.plot(c["aHH"] / c["h"], c["a"] / c["h"], "o", label=f"{c['name']}: max_wave_amplitude_m")
        ax.plot(c["aHH"] / c["h"], c["g"] / c["h"], "s", mfc="none", color=line.get_color(),
                label=f"{c['name']}: gauges, flat bed")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel("a_M / h, Heller & Hager", fontsize=8)
    ax.set_ylabel("a_M / h, dsdem", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=5)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("-o", "--out", default=".")
    a = ap.parse_args()
    xs = gauge_positions()
    cases = [read_case(p, xs) for p in a.runs]
    lines = tables(cases)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    try:
        plot(cases, xs, os.path.join(a.out, "impulse_wave.png"))
    except ImportError:
        print("matplotlib not available: no plot")


if __name__ == "__main__":
    main()
