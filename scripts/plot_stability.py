#!/usr/bin/env python3
"""Plots of `dsdem stability OUT`: OUT/fs_displacement.png, OUT/stability_trials.png and
OUT/mechanism*.png.

    plot_stability.py OUT

fs_displacement.png: the largest displacement since the settled state at the end of each
trial against the trial's F (stood: filled, failed: open, undecided: a cross), one curve per
variant, the factor of safety marked. stability_trials.png: each static and pseudo-static
trial's unbalanced force ratio and monitored displacement against its steps (OUT/trials.csv),
coloured by F; solid: stood, dashed: failed, dotted: undecided. mechanism[_pseudo_static].png: the lowest F that failed, the
mesh coloured by the displacement since the settled state, broken joints in black (needs
meshio; skipped without it).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_fs(out: Path, s: dict) -> None:
    fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
    colours = {"static": "tab:blue", "pseudo_static": "tab:red", "dynamic": "tab:green"}
    keys = {"static": "factor_of_safety", "pseudo_static": "factor_of_safety_pseudo_static",
            "dynamic": "factor_of_safety_dynamic"}
    for variant in ("static", "pseudo_static", "dynamic"):
        tr = sorted((t for t in s["trials"] if t["variant"] == variant and not t.get("budget_check")),
                    key=lambda t: t["F"])
        if not tr:
            continue
        F = np.array([t["F"] for t in tr])
        d = np.maximum(np.array([t["max_displacement_m"] for t in tr]), 1e-12)
        ok = np.array([t["result"] in ("equilibrium", "survived") for t in tr])
        failed = np.array([t["result"] == "failed" for t in tr])
        undecided = ~ok & ~failed
        c = colours[variant]
        ax.plot(F, d, "-", color=c, lw=1, label=variant.replace("_", "-"))
        ax.plot(F[ok], d[ok], "o", color=c, label=f"{variant.replace('_', '-')}: stands")
        ax.plot(F[failed], d[failed], "o", mfc="none", color=c, label=f"{variant.replace('_', '-')}: fails")
        if undecided.any():
            ax.plot(F[undecided], d[undecided], "x", color=c, label=f"{variant.replace('_', '-')}: undecided")
        if keys[variant] in s:
            fs = s[keys[variant]]
            ax.axvline(fs, color=c, ls="--", lw=1)
            ax.annotate(f"FS = {fs:.3f}", (fs, 0.98), xycoords=("data", "axes fraction"), color=c,
                        ha="right", va="top", rotation=90)
    ax.set_yscale("log")
    ax.set_xlabel("strength reduction factor F")
    ax.set_ylabel("largest displacement since the settled state [m]")
    ax.set_title(f"Strength reduction: {s.get('title') or out.name}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.savefig(out / "fs_displacement.png", dpi=120)
    plt.close(fig)


def plot_trials(out: Path, s: dict) -> None:
    """Convergence of every trial: unbalanced force ratio and monitored displacement against steps."""
    path = out / "trials.csv"
    if not path.is_file():
        return
    data = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    if data.size == 0:
        return
    data = np.atleast_1d(data)
    variants = [v for v in ("static", "pseudo_static") if (data["variant"] == v).any()]
    fig, axes = plt.subplots(len(variants), 2, figsize=(12, 4.2 * len(variants)), layout="constrained",
                             squeeze=False)
    styles = {"equilibrium": "-", "failed": "--", "undecided": ":"}
    ratio = s.get("settings", {}).get("equilibrium_ratio", 1e-5)
    for row, variant in zip(axes, variants):
        sel = data[data["variant"] == variant]
        ranks = {F: i for i, F in enumerate(sorted(set(sel["F"].tolist())))}  # colour by rank: close F apart
        cmap = matplotlib.colormaps["viridis"]

        def norm(F, n=max(1, len(ranks) - 1)):
            return ranks[F] / n
        for k in np.unique(sel["trial"]):
            t = sel[sel["trial"] == k]
            label = f"F = {t['F'][0]:.4f} ({t['result'][0]}{', budget check' if t['budget_check'][0] else ''})"
            kw = dict(color=cmap(norm(t["F"][0])), ls=styles.get(t["result"][0], "-"), lw=1.2 if t["budget_check"][0] else 1.0)
            row[0].plot(t["step"], np.maximum(t["unbalanced_ratio"], 1e-12), label=label, **kw)
            row[1].plot(t["step"], np.maximum(t["displacement_m"], 1e-12), **kw)
        row[0].axhline(ratio, color="k", lw=0.8, ls="--")
        row[0].set_yscale("log")
        row[1].set_yscale("log")
        row[0].set_ylabel("unbalanced force ratio")
        row[1].set_ylabel("monitored displacement since settled [m]")
        for ax in row:
            ax.set_xlabel("steps of the trial")
            ax.grid(True, which="both", alpha=0.3)
        row[0].set_title(f"{variant.replace('_', '-')}: unbalanced force ratio (equilibrium below the dashed line)")
        row[1].set_title(f"{variant.replace('_', '-')}: displacement (solid stood, dashed failed, dotted undecided)")
        row[0].legend(fontsize=7, loc="upper right", ncol=2)
    fig.savefig(out / "stability_trials.png", dpi=110)
    plt.close(fig)


def mechanism_title(m, suffix: str) -> str:
    """'Mechanism at F = ... (variant)': the frame's time is the factor it failed at."""
    F = m.field_data.get("TimeValue")
    ftxt = f" at F = {float(np.ravel(F)[0]):.3f}" if F is not None else ""
    return f"Mechanism{ftxt} ({suffix.strip('_') or 'static'})"


def outer_faces(tet: np.ndarray) -> np.ndarray:
    """The triangles that bound a tetrahedral mesh: the faces only one tetrahedron has."""
    faces = np.concatenate([tet[:, [0, 1, 2]], tet[:, [0, 1, 3]], tet[:, [0, 2, 3]], tet[:, [1, 2, 3]]])
    key = np.sort(faces, axis=1)
    _, first, count = np.unique(key, axis=0, return_index=True, return_counts=True)
    return faces[first[count == 1]]


def plot_mechanism_3d(out: Path, suffix: str, m, tet: np.ndarray) -> None:
    """A 3D model's mechanism: its outer surface in perspective, coloured by the displacement
    since the settled state."""
    from matplotlib import cm, colors
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    mag = np.linalg.norm(m.point_data["displacement_since_settled_m"], axis=1)
    faces = outer_faces(tet)
    norm = colors.Normalize(vmin=0.0, vmax=max(float(mag.max()), 1e-30))
    fig = plt.figure(figsize=(9, 6), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    poly = Poly3DCollection(m.points[faces], facecolors=cm.viridis(norm(mag[faces].mean(axis=1))),
                            edgecolors="none")
    ax.add_collection3d(poly)
    lo, hi = m.points.min(axis=0), m.points.max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(np.maximum(hi - lo, 1e-9 * max(hi - lo)))
    ax.view_init(elev=25, azim=-60)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # a thin model gets no crowded ticks
        axis.set_major_locator(plt.MaxNLocator(4))
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, shrink=0.7,
                 label="displacement since the settled state [m]")
    ax.set_title(mechanism_title(m, suffix) + ", 3D: the outer surface")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    fig.savefig(out / f"mechanism{suffix}.png", dpi=120)
    plt.close(fig)


def plot_mechanism(out: Path, suffix: str, s: dict) -> None:
    try:
        import meshio
    except ImportError:
        return
    vtu = out / f"mechanism{suffix}.vtu"
    if not vtu.exists():
        return
    m = meshio.read(vtu)
    tet = next((c.data for c in m.cells if c.type == "tetra"), None)
    if tet is not None:
        plot_mechanism_3d(out, suffix, m, tet)
        return
    tri = next(c.data for c in m.cells if c.type == "triangle")
    du = m.point_data["displacement_since_settled_m"][:, :2]
    mag = np.linalg.norm(du, axis=1)
    fig, ax = plt.subplots(figsize=(9, 6), layout="constrained")
    tpc = ax.tripcolor(m.points[:, 0], m.points[:, 1], tri, mag, shading="gouraud", cmap="viridis")
    fig.colorbar(tpc, ax=ax, label="displacement since the settled state [m]")
    cracks = out / f"mechanism_cracks{suffix}.vtu"
    if cracks.exists():
        c = meshio.read(cracks)
        lines = next((b.data for b in c.cells if b.type == "line"), None)
        broken = None
        for k in ("broken", "state"):
            if k in c.cell_data:
                broken = np.asarray(c.cell_data[k][0]).ravel() > 0
                break
        if lines is not None and broken is not None:
            for a, b in lines[broken]:
                ax.plot(c.points[[a, b], 0], c.points[[a, b], 1], "k-", lw=0.8)
    ax.set_title(mechanism_title(m, suffix) + ": broken joints in black")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    fig.savefig(out / f"mechanism{suffix}.png", dpi=120)
    plt.close(fig)


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    try:
        s = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError) as e:
        print(f"error: {out / 'summary.json'}: {e}", file=sys.stderr)
        return 2
    plot_fs(out, s)
    plot_trials(out, s)
    for suffix in ("", "_pseudo_static"):
        plot_mechanism(out, suffix, s)
    return 0


if __name__ == "__main__":
    sys.exit(main())
