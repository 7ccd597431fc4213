#!/usr/bin/env python3
"""Plots for `dsdem wave generate` and `dsdem wave spectrum`.

--wave CSV      t_s,a_mps2,v_mps,d_m (optional): acceleration, velocity, displacement
--spectrum CSV  period_s,Sa_mps2,Sv_mps,Sd_m[,target_Sa_mps2]: Sa against the target
--png PNG       output picture
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--wave")
    p.add_argument("--spectrum", required=True)
    p.add_argument("--png", required=True)
    p.add_argument("--title", default="")
    args = p.parse_args()

    s = read_csv(args.spectrum)
    if args.wave:
        w = read_csv(args.wave)
        fig = plt.figure(figsize=(12, 8))
        grid = fig.add_gridspec(3, 2, width_ratios=[1.6, 1.0])
        rows = [("a_mps2", "acceleration (m/s$^2$)"), ("v_mps", "velocity (m/s)"), ("d_m", "displacement (m)")]
        for i, (key, label) in enumerate(rows):
            ax = fig.add_subplot(grid[i, 0])
            ax.plot(w["t_s"], w[key], lw=0.8, color="C0")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            if i == 2:
                ax.set_xlabel("time (s)")
        ax = fig.add_subplot(grid[:, 1])
    else:
        fig, ax = plt.subplots(figsize=(8, 6))

    T = s["period_s"]
    ax.loglog(T, s["Sa_mps2"], color="C0", lw=1.2, label="computed Sa")
    if "target_Sa_mps2" in s:
        tgt = s["target_Sa_mps2"]
        ax.loglog(T, tgt, "k--", lw=1.2, label="target")
        ax.fill_between(T, 0.9 * tgt, 1.1 * tgt, color="0.85", label="target $\\pm$10%")
    ax.set_xlabel("period (s)")
    ax.set_ylabel("spectral acceleration Sa (m/s$^2$)")
    ax.grid(which="both", alpha=0.3)
    ax.legend()
    if args.title:
        fig.suptitle(args.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
