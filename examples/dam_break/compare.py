#!/usr/bin/env python3
"""Dam break: dsdem's SPH water against Koshizuka & Oka (1996) and Martin & Moyce (1952).

Usage: compare.py OUT/dam_break.csv [more.csv ...] [-o dam_break.png]
Prints the largest relative errors of the surge front and the column height at the
reference times (linear interpolation of the run's samples) and draws both curves.
"""
import argparse
import csv
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def read_reference():
    ref = {}
    with open(os.path.join(HERE, "reference.csv")) as f:
        rows = [r for r in f if not r.startswith("#")]
    for r in list(csv.DictReader(rows)):
        ref.setdefault((r["source"], r["quantity"]), []).append((float(r["time"]), float(r["value"])))
    return ref


def read_run(path):
    with open(path) as f:
        rows = [r for r in f if not r.startswith("#")]
    data = list(csv.DictReader(rows))
    return {k: [float(d[k]) for d in data] for k in ("T", "Z", "tau", "H")}


def interp(ts, vs, t):
    for k in range(1, len(ts)):
        if ts[k] >= t:
            w = (t - ts[k - 1]) / (ts[k] - ts[k - 1])
            return (1 - w) * vs[k - 1] + w * vs[k]
    return vs[-1]


def errors(run, ref, delay=0.0):
    out = {}
    for (src, q), pts in ref.items():
        t_key, v_key = ("T", "Z") if q == "Z" else ("tau", "H")
        shift = delay if (src, q) == ("martin_moyce", "Z") else 0.0
        out[(src, q)] = max(abs(interp(run[t_key], run[v_key], max(0.0, t - shift)) - v) / v for t, v in pts)
    return out


def gate_delay(run, ref):
    """Martin & Moyce's gate delay in T (0 to 0.3): the shift with the least largest error."""
    return min((errors(run, ref, 0.01 * d)[("martin_moyce", "Z")], 0.01 * d) for d in range(31))[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("-o", "--out", default="dam_break.png")
    args = ap.parse_args()
    ref = read_reference()
    runs = [(p, read_run(p)) for p in args.runs]
    for p, run in runs:
        for (src, q), e in sorted(errors(run, ref).items()):
            print(f"{p}: {src} {q}: largest relative error {100 * e:.1f} %")
        d = gate_delay(run, ref)
        e = errors(run, ref, d)[("martin_moyce", "Z")]
        print(f"{p}: martin_moyce Z with their gate delay fitted (T - {d:.2f}): {100 * e:.1f} %")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no plot")
        return
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for p, run in runs:
        label = os.path.basename(os.path.dirname(os.path.abspath(p))) or p
        a1.plot(run["T"], run["Z"], label=f"dsdem SPH ({label})")
        a2.plot(run["tau"], run["H"], label=f"dsdem SPH ({label})")
    marks = {"koshizuka_oka": ("s", "Koshizuka & Oka 1996"), "martin_moyce": ("o", "Martin & Moyce 1952")}
    for (src, q), pts in ref.items():
        ax = a1 if q == "Z" else a2
        ax.plot([t for t, _ in pts], [v for _, v in pts], marks[src][0], mfc="none", label=marks[src][1])
    a1.set_xlabel("T = t sqrt(2g/a)")
    a1.set_ylabel("Z = front / a")
    a1.set_xlim(0, 3.3)
    a2.set_xlabel("tau = t sqrt(g/a)")
    a2.set_ylabel("H = height / (2a)")
    a2.set_xlim(0, 2.3)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
