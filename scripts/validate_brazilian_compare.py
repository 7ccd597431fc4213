#!/usr/bin/python3
"""Brazilian disc: compare several runs (docs/validation.md).

    python3 scripts/validate_brazilian_compare.py LABEL=OUT [LABEL=OUT ...] [--plot FILE.png] [--table]

OUT is the output folder of a run post-processed by validate_brazilian.py (its
validation.json, or validation_stress.json for --stress-only runs). --plot draws the
error profiles of the stress check along both diameters (sigma_xx and sigma_yy, each
relative to max(|analytic|, sigma_0)) of every run in one figure; --table prints a
Markdown table of the peak load, the tensile strength and its error, the crack times
and the stress-check maxima of the runs that reached the peak.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(out: str) -> dict:
    for name in ("validation.json", "validation_stress.json"):
        path = os.path.join(out, name)
        if os.path.exists(path):
            with open(path) as f:
                d = json.load(f)
            return d if "stress_check" in d else {"stress_check": d}
    raise FileNotFoundError(f"{out}: no validation.json or validation_stress.json (run validate_brazilian.py first)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=OUT")
    ap.add_argument("--plot", help="PNG of the stress-check error profiles")
    ap.add_argument("--table", action="store_true", help="Markdown table of the runs that reached the peak")
    args = ap.parse_args()
    runs = []
    for r in args.runs:
        label, _, out = r.partition("=")
        runs.append((label, load(out)))

    if args.table:
        print("| run | triangles | peak load (kN/m) | sigma_t (MPa) | error | first crack (ms) | at (R) | "
              "through crack (ms) | stress: loaded xx / yy | unloaded xx / yy | wall (s) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for label, d in runs:
            if "peak_load_N" not in d:
                continue
            sc = d["stress_check"]["diameters"]

            def pc(v):
                return "-" if v is None else f"{100 * v:.1f} %"

            def ms(v):
                return "-" if v is None else f"{1e3 * v:.2f}"
            print(f"| {label} | {d.get('elements')} | {d['peak_load_N'] / 1e3:.1f} | {d['tensile_strength_Pa'] / 1e6:.3f} | "
                  f"{100 * d['relative_error']:+.2f} % | {ms(d.get('t_first_crack_s'))} | "
                  f"{d.get('first_crack_distance_from_centre_over_R', float('nan')):.3f} | {ms(d.get('t_through_crack_s'))} | "
                  f"{pc(sc['loaded']['max_error_sigma_xx'])} / {pc(sc['loaded']['max_error_sigma_yy'])} | "
                  f"{pc(sc['unloaded']['max_error_sigma_xx'])} / {pc(sc['unloaded']['max_error_sigma_yy'])} | "
                  f"{d.get('wall_time_s') or 0:.0f} |")

    if args.plot:
        fig, axs = plt.subplots(2, 2, figsize=(10, 5.6), sharex=True, sharey=True)
        for j, name in enumerate(("loaded", "unloaded")):
            for i, comp in enumerate(("xx", "yy")):
                ax = axs[i, j]
                for k, (label, d) in enumerate(runs):
                    prof = d["stress_check"]["diameters"][name].get("profile")
                    if prof is None:
                        continue
                    ax.plot(prof["rho"], 100 * np.array(prof[f"error_{comp}"], dtype=float), "-o", ms=2.2, lw=0.9,
                            color=f"C{k}", label=label)
                lim = runs[0][1]["stress_check"]["diameters"][name]["range_rho"]
                ax.axvspan(-1, -lim, color="0.9")
                ax.axvspan(lim, 1, color="0.9")
                ax.axhline(5, color="r", lw=0.8, ls="--")
                ax.set_xlim(-1, 1)
                ax.set_ylim(0, 20)
                ax.grid(alpha=0.3)
                ax.set_title(f"{name} diameter, $\\sigma_{{{comp}}}$", fontsize=9)
                if j == 0:
                    ax.set_ylabel("error (%)")
                if i == 1:
                    ax.set_xlabel("y / R" if name == "loaded" else "x / R")
        axs[0, 0].legend(fontsize=7, loc="upper center")
        fig.suptitle("Stress check: error of the band-mean stresses against Hondros (measured contact width), "
                     "relative to max(|analytic|, $\\sigma_0$); shaded: not checked", fontsize=9)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
