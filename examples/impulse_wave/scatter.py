#!/usr/bin/env python3
"""The impulse-wave cases over several settles (scatter.sh): each case's ratios to Heller &
Hager's a_M, mean, standard deviation and range, for max_wave_amplitude_m and for the largest
crest at the gauges over the flat bed (compare.py's two measures); and at each gauge the primary
wave's crest and height against Heller & Hager's decay laws at its distance.

Usage: scatter.py OUT_ROOT   (OUT_ROOT/settle_*/{A,B,C}); writes OUT_ROOT/scatter.md.
"""
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare import gauge_positions, read_case  # noqa: E402


def main():
    root = sys.argv[1]
    xs = gauge_positions()
    runs = sorted(glob.glob(os.path.join(root, "settle_*")))
    rows = ["| case | runs | a_M H&H (m) | F | max_wave_amplitude_m / a_M: mean, sd (range) | "
            "largest gauge crest / a_M: mean, sd (range) |", "|---|---|---|---|---|---|"]
    by_case = {name: [read_case(os.path.join(r, name), xs) for r in runs if os.path.isdir(os.path.join(r, name))]
               for name in ("A", "B", "C")}
    for name, cases in by_case.items():
        if not cases:
            continue
        a = [c["a"] / c["aHH"] for c in cases]
        g = [c["g"] / c["aHH"] for c in cases]
        sd = (lambda v: statistics.stdev(v) if len(v) > 1 else 0.0)
        rows.append(f"| {name} | {len(cases)} | {min(c['aHH'] for c in cases):.3f}-{max(c['aHH'] for c in cases):.3f} | "
                    f"{min(c['F'] for c in cases):.2f}-{max(c['F'] for c in cases):.2f} | "
                    f"{statistics.mean(a):.2f}, {sd(a):.2f} ({min(a):.2f}-{max(a):.2f}) | "
                    f"{statistics.mean(g):.2f}, {sd(g):.2f} ({min(g):.2f}-{max(g):.2f}) |")
    rows += ["", "The primary wave at each gauge against Heller & Hager's decay laws a(x) and H(x): mean, sd (range) "
             "over the runs that saw it (a height needs the trough after the crest before the run's end).", "",
             "| case | gauge | x/h | crest / a(x) | crest to trough / H(x) |", "|---|---|---|---|---|"]

    def stats(v):
        if not v:
            return "-"
        sd = statistics.stdev(v) if len(v) > 1 else 0.0
        return f"{statistics.mean(v):.2f}, {sd:.2f} ({min(v):.2f}-{max(v):.2f}), {len(v)} runs"

    for name, cases in by_case.items():
        if not cases or not cases[0]["decay"]:
            continue
        for i, g in enumerate(cases[0]["decay"]):
            crest = [c["decay"][i]["crest_ratio"] for c in cases if isinstance(c["decay"][i]["crest_ratio"], float)]
            height = [c["decay"][i]["height_ratio"] for c in cases if isinstance(c["decay"][i]["height_ratio"], float)]
            rows.append(f"| {name} | {g['name']} | {g['relative_distance']:.2f} | {stats(crest)} | {stats(height)} |")
    with open(os.path.join(root, "scatter.md"), "w") as f:
        f.write("\n".join(rows) + "\n")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
