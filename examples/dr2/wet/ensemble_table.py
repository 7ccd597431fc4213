#!/usr/bin/python3
"""The wave of Dr2's shear sliding into the reservoir over an ensemble (docs/dr2.md §10).

Usage: ensemble_table.py ENSEMBLE_OUT [ENSEMBLE_OUT ...]
Each ENSEMBLE_OUT is a `dsdem ensemble` of examples/dr2/ensembles/shear_sliding_wet.yaml (the
members in ENSEMBLE_OUT/members/NNNN). Per member, as table.py reads a single run: the first
crest over the far bank (gauge g830's highest surface within 15 s of the slide's entry) and the
run-up on the far bank, both above reservoir.level (837 m; the settled water stands 1-1.5 m
below it), the largest force on the intake, the mean of the gauges' largest displacements. Prints a table per ensemble (mean, standard deviation, range) and,
for two ensembles of the same members (the same sampling), the member-by-member differences.
"""
import csv
import json
import math
import os
import statistics
import sys

KEYS = [("crest", "first crest over the far bank (m)"), ("runup", "run-up, far bank (m)"),
        ("intake", "intake peak force (MN/m)"), ("disp", "mean max displacement (m)")]


def member(path):
    with open(os.path.join(path, "summary.json")) as f:
        s = json.load(f)
    m = s["moving_water"]
    level = s["heller_hager"]["still_level_m"]  # reservoir.level, which the gauges read from
    entry = s["heller_hager"].get("impact_time_s")
    with open(os.path.join(path, "history.csv")) as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    crest = math.nan
    if entry is not None:
        etas = [float(r["g830_eta_m"]) for r in rows
                if entry <= float(r["time_s"]) <= entry + 15.0 and r["g830_eta_m"] not in ("", "nan", "NaN")]
        crest = max(etas) if etas else math.nan
    runup = m["runup"].get("far_bank", {}).get("elevation_m")
    force = m["force_on_curves"].get("intake", {}).get("max_force_N_per_m")
    return {"crest": crest, "runup": runup - level if runup is not None else math.nan,
            "intake": force / 1e6 if force is not None else math.nan,
            "disp": s.get("mean_max_displacement_m", math.nan)}


def ensemble(root):
    out = {}
    members = os.path.join(root, "members")
    for name in sorted(os.listdir(members)):
        path = os.path.join(members, name)
        if os.path.exists(os.path.join(path, "summary.json")):
            out[name] = member(path)
    return out


def stats(values):
    v = [x for x in values if not math.isnan(x)]
    if not v:
        return "-"
    sd = statistics.stdev(v) if len(v) > 1 else 0.0
    return f"{statistics.mean(v):.1f} ± {sd:.1f} ({min(v):.1f}-{max(v):.1f})"


def main(roots):
    runs = [(root, ensemble(root)) for root in roots]
    print("| ensemble | members | " + " | ".join(label for _, label in KEYS) + " |")
    print("|---|---|" + "---|" * len(KEYS))
    for root, ms in runs:
        print(f"| {root} | {len(ms)} | " + " | ".join(stats([m[k] for m in ms.values()]) for k, _ in KEYS) + " |")
    if len(runs) == 2:
        (ra, a), (rb, b) = runs
        both = sorted(set(a) & set(b))
        print(f"\nMember by member, {rb} less {ra} ({len(both)} members):\n")
        print("| member | " + " | ".join(label for _, label in KEYS) + " |")
        print("|---|" + "---|" * len(KEYS))
        for name in both:
            print(f"| {name} | " + " | ".join(f"{a[name][k]:.1f} -> {b[name][k]:.1f}" for k, _ in KEYS) + " |")
        print("| difference | " + " | ".join(stats([b[n][k] - a[n][k] for n in both]) for k, _ in KEYS) + " |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
