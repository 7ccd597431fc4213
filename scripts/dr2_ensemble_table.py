#!/usr/bin/python3
"""The Dr2 ensembles against the paper (docs/dr2.md, the headline table).

Reads OUT/ensemble.json of `dsdem ensemble examples/dr2/ensembles/<mode>.yaml -o OUT` for
each mode given and prints a Markdown table: P10 / P50 / P90 of the mean max displacement,
of each gauge's max displacement and of the peak velocities at gauges 1 and 2, the river
blocked time, the debris over the intake; the probabilities of the river blocked and the
intake reached (95 % Wilson interval); the paper's value beside each.

  scripts/dr2_ensemble_table.py shear_sliding=OUT1 local_collapse=OUT2 slip_j1=OUT3 [label=OUT ...]

A label is the paper's mode name (shear_sliding, local_collapse, slip_j1), optionally with
a suffix after a colon for a second ensemble of the same mode (shear_sliding:4m=OUT4).
"""
import csv
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PAPER = os.path.join(HERE, "..", "..", "shared", "reference", "paper_results.json")


def paper_values():
    for path in (PAPER, os.environ.get("DSDEM_PAPER_RESULTS", "")):
        if path and os.path.exists(path):
            with open(path) as f:
                return json.load(f)["dr2"]
    return {}


def pct(s, digits=0):
    if s is None:
        return "-"
    f = f"{{:.{digits}f}}"
    return " / ".join(f.format(s[q]) for q in ("p10", "p50", "p90"))


def prob(e):
    if e is None:
        return "-"
    lo, hi = e["wilson95"]
    return f"{e['probability']:.2f} [{lo:.2f}, {hi:.2f}] ({e['count']} of {e['n']})"


def spans(xs, ps, level):
    """The x intervals (m) where the probability is at least `level`, as text."""
    out, start, last = [], None, None
    for x, q in zip(xs, ps):
        if q >= level and start is None:
            start = x
        if q < level and start is not None:
            out.append(f"{start:.0f}-{last:.0f}")
            start = None
        last = x
    if start is not None:
        out.append(f"{start:.0f}-{last:.0f}")
    return ", ".join(out) if out else "none"


def hazard_rows(out):
    path = os.path.join(out, "deposit_hazard.csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        rows = list(csv.DictReader(f))
    xs = [float(r["x_m"]) for r in rows]
    result = []
    for key in ("p_thicker_than_10_m", "p_thicker_than_1_m"):
        if key not in rows[0]:
            continue
        d = key.split("_")[-2]
        ps = [float(r[key]) for r in rows]
        result.append((f"x (m) with debris > {d} m: P >= 0.5 / P >= 0.1",
                       f"{spans(xs, ps, 0.5)} / {spans(xs, ps, 0.1)}", ""))
    return result


def rows_for(mode, ens, paper):
    sc, ev = ens["scalars"], ens["events"]
    p = paper.get(mode, {})
    g = p.get("gauge_max_displacement_m", [None] * 4)
    v = p.get("peak_velocity_mps", {})
    rows = [("members (completed / failed)", f"{ens['completed_members']} / {ens['failed_members']}", "")]
    rows.append(("mean max displacement (m)", pct(sc.get("mean_max_displacement_m")),
                 str(p.get("mean_max_displacement_m", "-"))))
    for k in range(4):
        rows.append((f"gauge {k + 1} max displacement (m)", pct(sc.get(f"gauges.gauge{k + 1}.max_displacement_m")),
                     "-" if g[k] is None else str(g[k])))
    for k in (1, 2):
        rows.append((f"gauge {k} peak velocity (m/s)", pct(sc.get(f"gauges.gauge{k}.peak_velocity_mps"), 1),
                     str(v.get(f"gauge{k}", "-"))))
    rows.append(("river blocked at (s)", pct(sc.get("river_blocked_time_s"), 1), str(p.get("river_blocked_time_s", "-"))))
    rows.append(("debris over the intake (m)", pct(sc.get("intake_debris_height_m")), "-"))
    blocked = p.get("river_blocked")
    rows.append(("P(river blocked)", prob(ev.get("river_blocked")),
                 "blocked" if blocked or "river_blocked_time_s" in p else "-"))
    rows.append(("P(intake reached)", prob(ev.get("intake_reached")), ""))
    intake_paper = p.get("intake_blocked")
    rows.append(("P(intake blocked, >= 10 m)", prob(ev.get("intake_blocked")),
                 "" if intake_paper is None else ("blocked" if intake_paper else "not blocked")))
    return rows


def main(argv):
    if len(argv) < 2 or any("=" not in a for a in argv[1:]):
        print(__doc__, file=sys.stderr)
        return 2
    paper = paper_values()
    for arg in argv[1:]:
        label, out = arg.split("=", 1)
        mode = label.split(":")[0]
        with open(os.path.join(out, "ensemble.json")) as f:
            ens = json.load(f)
        print(f"\n#### {label.replace(':', ', ')}: {ens.get('title', '')}\n")
        print("| quantity | dsdem P10 / P50 / P90 | paper |")
        print("|---|---|---|")
        for name, value, ref in rows_for(mode, ens, paper) + hazard_rows(out):
            print(f"| {name} | {value} | {ref} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
