#!/usr/bin/env python3
"""dsdem plot: PNG plots of a run's histories (OUT/history.csv) into OUT/plots/.

    plot_history.py OUT [--no-show-stages] [--quiet]

Figures (each only when its columns exist):
  gauge_displacement.png             |u| of every gauge vs time (max marked)
  gauge_displacement_components.png  u_x and u_y of every gauge
  gauge_velocity.png                 |v| of every gauge (peak marked)
  gauge_acceleration.png             |a| of every gauge
  energies.png                       every *_J_per_m column, energy balance error on a 2nd axis
  water_surface.png                  moving water: free-surface elevation at every gauge
  wave_amplitude.png                 moving water: the wave's amplitude and its envelope (running max)
  wave_decay.png                     moving water: the primary wave's height and crest at the gauges against the
                                     distance from the shoreline, beside Heller & Hager's H(x) and a(x)
  water_runup.png                    moving water: run-up on every bank, water past every crest
  water_forces.png                   moving water: force and peak pressure on every named curve
  fracture.png                       broken joints, damaged joints, fragments vs time
  contacts.png                       contact counts vs time
  loads.png                          reactions / loads / forces vs time
  load_displacement.png              reaction vs the matching displacement column
  other.png                          any remaining column, so nothing new goes unseen
Columns are discovered by name pattern, never by position.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dsdem_plotlib as lib  # noqa: E402
import dsdem_water as wat  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

_BASE = {"time_s", "step", "stage"}
_COUNT_FRACTURE = re.compile(r"(^|_)(broken|damaged|fragments?|cracks?)(_|$)")
_COUNT_CONTACT = re.compile(r"(^|_)contacts?(_|$)")
_LOAD = re.compile(r"(^|_)(reaction|load|force|plate)(_|$)")


def _fig(height: float = 5.0):
    fig, ax = plt.subplots(figsize=(9.5, height), layout="constrained")
    return fig, ax


class Plotter:
    def __init__(self, out: Path, show_stages: bool, quiet: bool):
        self.out = out
        self.plots = out / "plots"
        self.show_stages = show_stages
        self.quiet = quiet
        self.h = lib.read_history(out / "history.csv")
        if self.h.data.shape[0] == 0:
            raise lib.InputError(f"{out / 'history.csv'}: no data rows yet")
        self.t = self.h.time
        self.summary = lib.read_summary(out)
        self.run_title = self.summary.get("title") or out.name
        self.used: set[str] = set(_BASE)
        self.written: list[Path] = []
        self.stage_changes = self._stage_changes()

    # ---------------------------------------------------------------- helpers
    def _stage_changes(self) -> list[tuple[float, str]]:
        if not self.h.has("stage"):
            return []
        s = self.h.col("stage")
        names = lib.stage_names(self.out)
        changes = []
        for i in np.nonzero(np.diff(s) != 0)[0]:
            k = int(s[i + 1])
            changes.append((float(self.t[i + 1]), names.get(k, f"stage {k + 1}")))
        if changes:  # name the first stage too, at t0
            k0 = int(s[0])
            changes.insert(0, (float(self.t[0]), names.get(k0, f"stage {k0 + 1}")))
        return changes

    def _stages(self, ax, labels: bool = True) -> None:
        """Dashed lines at stage changes; the stage names as ticks on a top axis (outside the
        data area, so legends never hide them)."""
        if not self.show_stages or not self.stage_changes:
            return
        for t, _ in self.stage_changes[1:]:
            ax.axvline(t, color="0.35", ls="--", lw=1.0, zorder=0.5)
        if labels:
            # A stage too short on this time axis for its name (a gravity stage before a long
            # earthquake) keeps its line but not its label, which would run into the next one.
            t0, t1 = float(np.nanmin(self.t)), float(np.nanmax(self.t))
            span = t1 - t0 if t1 > t0 else 1.0
            starts = [t for t, _ in self.stage_changes] + [t1]
            names = [n if (starts[i + 1] - t) / span >= 0.013 * len(n) or i + 1 == len(self.stage_changes) else ""
                     for i, (t, n) in enumerate(self.stage_changes)]
            top = ax.secondary_xaxis("top")
            top.set_xticks([t for t, _ in self.stage_changes], names)
            top.tick_params(axis="x", length=4, labelsize=9.5, labelcolor="0.3", direction="out")
            for lbl in top.get_xticklabels():
                lbl.set_fontstyle("italic")
                lbl.set_horizontalalignment("left")
            top.spines["top"].set_visible(False)

    def _time_axis(self, ax) -> None:
        ax.set_xlabel("Time (s)")
        t0, t1 = float(np.nanmin(self.t)), float(np.nanmax(self.t))
        if t1 > t0:
            ax.set_xlim(t0, t1)

    def _save(self, fig, name: str) -> None:
        self.plots.mkdir(parents=True, exist_ok=True)
        path = self.plots / name
        tmp = path.with_suffix(".tmp.png")
        fig.savefig(tmp)
        plt.close(fig)
        tmp.replace(path)
        self.written.append(path)

    def _scaled(self, cols: list[np.ndarray], unit: str) -> tuple[float, str]:
        m = max((float(np.nanmax(np.abs(c))) if c.size and np.isfinite(c).any() else 0.0) for c in cols)
        return lib.autoscale(m, unit)

    def _legend(self, ax, n: int) -> None:
        if n == 0:
            return
        if n > 8:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), ncols=1 + n // 20)
        else:
            ax.legend(loc="best")

    # ---------------------------------------------------------------- gauges
    def gauges(self) -> list[str]:
        names = []
        for n in self.h.names:
            m = re.match(r"^(.+)_displacement_x_m$", n)
            if m and self.h.has(f"{m.group(1)}_displacement_y_m"):
                names.append(m.group(1))
        return names

    def _gauge_vector(self, g: str, what: str, unit_suffix: str):
        cx, cy = f"{g}_{what}_x_{unit_suffix}", f"{g}_{what}_y_{unit_suffix}"
        if not (self.h.has(cx) and self.h.has(cy)):
            return None
        self.used.update({cx, cy})
        x, y = self.h.col(cx), self.h.col(cy)
        return x, y, np.hypot(x, y)

    def gauge_magnitude(self, what: str, unit_suffix: str, unit: str, fname: str, title: str, mark: str):
        series = []
        for g in self.gauges():
            v = self._gauge_vector(g, what, unit_suffix)
            if v is not None:
                series.append((g, v[2]))
        if not series:
            return
        fig, ax = _fig()
        f, u = self._scaled([s for _, s in series], unit)
        for g, s in series:
            label = g
            if s.size and np.isfinite(s).any():
                i = int(np.nanargmax(s))
                fu = lib.autoscale(float(s[i]), unit)
                val = f"{s[i] * fu[0]:.3g} {fu[1]}"
                label = f"{g} ({mark} {val} at {self.t[i]:.3g} s)" if mark == "peak" else f"{g} ({mark} {val})"
                (line,) = ax.plot(self.t, s * f, label=label)
                ax.plot(self.t[i], s[i] * f, "o", color=line.get_color(), ms=5, zorder=3)
        self._time_axis(ax)
        ax.set_ylabel(lib.axis_label(f"{what.capitalize()} magnitude", u))
        ax.set_ylim(bottom=0)
        lib.title_pair(ax, title, self.run_title)
        self._legend(ax, len(series))
        self._stages(ax)
        self._save(fig, fname)

    def gauge_components(self):
        series = []
        for g in self.gauges():
            v = self._gauge_vector(g, "displacement", "m")
            if v is not None:
                series.append((g, v[0], v[1]))
        if not series:
            return
        fig, axes = plt.subplots(2, 1, figsize=(9.5, 7.0), sharex=True, layout="constrained")
        f, u = self._scaled([s[k] for s in series for k in (1, 2)], "m")  # one unit for both panels
        for ax, k, comp in ((axes[0], 1, "Horizontal displacement $u_x$"), (axes[1], 2, "Vertical displacement $u_y$")):
            for s in series:
                ax.plot(self.t, s[k] * f, label=s[0])
            ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
            ax.set_ylabel(lib.axis_label(comp, u))
            self._stages(ax, labels=k == 1)
        self._time_axis(axes[1])
        lib.title_pair(axes[0], "Gauge displacement components", self.run_title)
        self._legend(axes[0], len(series))
        self._save(fig, "gauge_displacement_components.png")

    # ---------------------------------------------------------------- moving water
    def _impact(self, ax) -> None:
        """The slide's entry into the water (summary.json heller_hager), a dotted line."""
        t = (self.summary.get("heller_hager") or {}).get("impact_time_s")
        if isinstance(t, (int, float)):
            ax.axvline(t, color="0.3", ls=":", lw=1.2, zorder=0.5, label=f"slide enters the water ({t:.3g} s)")

    def _heller_hager(self, ax, key: str, what: str) -> None:
        v = (self.summary.get("heller_hager") or {}).get(key)
        if isinstance(v, (int, float)):
            ax.axhline(v, color="tab:red", ls="--", lw=1.2, zorder=0.5, label=f"Heller & Hager {what} {v:.3g} m")

    def water_surface(self, w: wat.WaterColumns):
        if not w.gauges:
            return
        fig, ax = _fig()
        for g, c in w.gauges:
            y = self.h.col(c)
            (line,) = ax.plot(self.t, y, label=g)
            if np.isfinite(y).any():
                i = int(np.nanargmax(y))
                ax.plot(self.t[i], y[i], "o", color=line.get_color(), ms=5, zorder=3)
                line.set_label(f"{g} (max {y[i]:.3g} m at {self.t[i]:.3g} s)")
            self.used.add(c)
        ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
        self._impact(ax)
        self._heller_hager(ax, "amplitude_m", "a_M")
        self._time_axis(ax)
        ax.set_ylabel("Free surface above reservoir.level (m)")
        lib.title_pair(ax, "Free surface at the gauges", self.run_title)
        self._legend(ax, len(w.gauges) + 2)
        self._stages(ax)
        self._save(fig, "water_surface.png")

    def wave_amplitude(self, w: wat.WaterColumns):
        if not w.amplitude:
            return
        fig, ax = _fig()
        a = self.h.col(w.amplitude)
        ax.plot(self.t, a, lw=1.0, color="tab:blue", alpha=0.7, label="amplitude (highest surface above the level)")
        env = np.fmax.accumulate(np.where(np.isfinite(a), a, -np.inf))
        ax.plot(self.t, env, lw=2.0, color="tab:blue", label="envelope (largest so far)")
        peak = (self.summary.get("moving_water") or {}).get("max_wave_amplitude") or {}
        if isinstance(peak.get("amplitude_m"), (int, float)):
            ax.plot(peak["time_s"], peak["amplitude_m"], "o", color="tab:blue", ms=6, zorder=3,
                    label=f"max {peak['amplitude_m']:.3g} m at x = {peak['x_m']:.4g} m, t = {peak['time_s']:.3g} s")
        self.used.add(w.amplitude)
        ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
        self._impact(ax)
        self._heller_hager(ax, "amplitude_m", "a_M")
        self._time_axis(ax)
        ax.set_ylabel("Wave amplitude (m)")
        lib.title_pair(ax, "Wave amplitude over the reservoir", self.run_title)
        ax.legend(loc="best")
        self._stages(ax)
        self._save(fig, "wave_amplitude.png")

    def wave_decay(self, w: wat.WaterColumns):
        """The primary wave at the gauges against their distance from the shoreline (summary.json
        heller_hager.gauges: the first crest after the slide's entry and crest to trough), beside
        Heller & Hager's 2D decay a(x) = (3/5) (P (x/h)^(-1/3))^(4/5) h and H(x) = (3/4) (...) h
        (docs/theory.md §12). A summary without that block: each gauge's highest surface and its
        range after the entry, against the distance from the entry point."""
        hh = self.summary.get("heller_hager") or {}
        P, h, t0 = hh.get("impulse_product"), hh.get("depth_m"), hh.get("impact_time_s")
        pts = []  # (gauge, distance, height or None, crest or None)
        if isinstance(hh.get("gauges"), list):
            origin = "the shoreline, where the slide met the level"
            for g in hh["gauges"]:
                pts.append((g["name"], g["distance_m"], g.get("height_m"), g.get("crest_m")))
        else:
            origin = "the slide's entry"
            entry = (hh.get("impact_point_m") or [None])[0]
            where = wat.gauge_positions(lib.load_yaml(lib.find_scenario(self.out, self.summary)))
            for g, c in w.gauges:
                if g not in where or not isinstance(entry, (int, float)) or not isinstance(t0, (int, float)):
                    continue
                y = self.h.col(c)[self.t >= t0]
                if y.size and np.isfinite(y).any():
                    pts.append((g, abs(where[g] - entry), float(np.nanmax(y)) - float(np.nanmin(y)),
                                float(np.nanmax(y))))
        if not pts or not all(isinstance(v, (int, float)) and v > 0 for v in (P, h)):
            return
        fig, ax = _fig()
        x = np.linspace(0.25 * h, max(max(p[1] for p in pts) * 1.3, hh.get("distance_of_max_height_m", 0) * 1.3), 200)
        decay = (P * (x / h) ** (-1 / 3)) ** 0.8 * h
        ax.plot(x, 0.75 * decay, color="tab:blue", ls="--", label="Heller & Hager H(x), wave height")
        ax.plot(x, 0.6 * decay, color="tab:cyan", ls=":", label="Heller & Hager a(x), crest")
        if isinstance(hh.get("height_m"), (int, float)) and isinstance(hh.get("distance_of_max_height_m"), (int, float)):
            ax.plot(hh["distance_of_max_height_m"], hh["height_m"], "s", color="tab:red", ms=7,
                    label=f"Heller & Hager H_M {hh['height_m']:.3g} m")
        heights = [p for p in pts if isinstance(p[2], (int, float))]
        crests = [p for p in pts if isinstance(p[3], (int, float))]
        ax.plot([p[1] for p in heights], [p[2] for p in heights], "o", color="tab:blue", ms=7,
                label="computed height: crest to trough after the entry")
        ax.plot([p[1] for p in crests], [p[3] for p in crests], "^", color="tab:cyan", ms=7,
                label="computed crest after the entry")
        for g, d, H, a in pts:
            y = H if isinstance(H, (int, float)) else a
            if isinstance(y, (int, float)):
                ax.annotate(g, (d, y), xytext=(5, 5), textcoords="offset points", fontsize=9)
        ax.set_xlabel(f"Distance from {origin} (m)")
        ax.set_ylabel("Wave height, crest (m)")
        ax.set_xlim(left=0)
        ax.set_ylim(bottom=0)
        lib.title_pair(ax, "The wave along the reservoir", self.run_title)
        ax.legend(loc="best")
        self._save(fig, "wave_decay.png")

    def water_runup(self, w: wat.WaterColumns):
        panels = [p for p in (w.runup, w.crests) if p]
        if not panels:
            return
        fig, axes = plt.subplots(len(panels), 1, figsize=(9.5, 1.5 + 3.5 * len(panels)), sharex=True,
                                 layout="constrained", squeeze=False)
        level = (self.summary.get("heller_hager") or {}).get("still_level_m")
        for ax, cols in zip(axes[:, 0], panels):
            for name, c in cols:
                y = self.h.col(c)
                label = name
                if np.isfinite(y).any():
                    i = int(np.nanargmax(y))
                    label += f" (max {y[i]:.4g} at {self.t[i]:.3g} s)"
                ax.plot(self.t, y, label=label)
                self.used.add(c)
            if cols is w.runup:
                if isinstance(level, (int, float)):
                    ax.axhline(level, color="0.5", lw=0.8, ls="--", zorder=0.5, label=f"reservoir.level {level:g} m")
                ax.set_ylabel("Run-up: highest water on the bank (m)")
            else:
                ax.set_ylabel("Water past the crest (m²/m)")
                ax.set_ylim(bottom=0)
            self._impact(ax)
            ax.legend(loc="best")
            self._stages(ax, labels=ax is axes[0, 0])
        self._time_axis(axes[-1, 0])
        lib.title_pair(axes[0, 0], "Run-up and overtopping", self.run_title)
        self._save(fig, "water_runup.png")

    def water_forces(self, w: wat.WaterColumns):
        if not w.forces:
            return
        pressures = dict(w.pressures)
        fig, axes = plt.subplots(2 if pressures else 1, 1, figsize=(9.5, 8.0 if pressures else 5.0), sharex=True,
                                 layout="constrained", squeeze=False)
        unit = lib.split_unit(w.forces[0][1])[1]
        mags = [np.hypot(self.h.col(x), self.h.col(y)) for _, x, y in w.forces]
        f, u = self._scaled(mags, unit)
        for (name, x, y), mag in zip(w.forces, mags):
            (line,) = axes[0, 0].plot(self.t, mag * f, label=f"{name} |F|")
            axes[0, 0].plot(self.t, self.h.col(x) * f, color=line.get_color(), lw=0.9, ls="--", label=f"{name} F_x")
            axes[0, 0].plot(self.t, self.h.col(y) * f, color=line.get_color(), lw=0.9, ls=":", label=f"{name} F_y")
            self.used.update({x, y})
        axes[0, 0].axhline(0, color="0.5", lw=0.8, zorder=0.5)
        axes[0, 0].set_ylabel(lib.axis_label("Force of the water", u))
        self._impact(axes[0, 0])
        axes[0, 0].legend(loc="best")
        if pressures:
            cols = list(pressures.values())
            fp, up = self._scaled([self.h.col(c) for c in cols], "Pa")
            for name, c in pressures.items():
                axes[1, 0].plot(self.t, self.h.col(c) * fp, label=name)
                self.used.add(c)
            axes[1, 0].set_ylabel(lib.axis_label("Peak pressure on the curve", up))
            self._impact(axes[1, 0])
            axes[1, 0].legend(loc="best")
        for i, ax in enumerate(axes[:, 0]):
            self._stages(ax, labels=i == 0)
        self._time_axis(axes[-1, 0])
        lib.title_pair(axes[0, 0], "Force of the water on curves", self.run_title)
        self._save(fig, "water_forces.png")

    def water(self):
        w = wat.water_columns(self.h.names)
        if not w:
            return
        self.water_surface(w)
        self.wave_amplitude(w)
        self.wave_decay(w)
        self.water_runup(w)
        self.water_forces(w)

    # ---------------------------------------------------------------- energies
    def energies(self):
        cols = [n for n in self.h.names if lib.split_unit(n)[1] == "J/m" and n not in self.used]
        if not cols:
            return
        fig, ax = _fig(5.5)
        f, u = self._scaled([self.h.col(c) for c in cols], "J/m")
        styles = {"kinetic": "-", "strain": "-", "gravity_potential": "-", "external_work": "-.", "water_work": "-."}
        lines = []
        # Twenty distinct colours (tab20's dark shades, then its light ones): a run with moving
        # water has more than tab10's ten energy curves, and a wrapped cycle gave two the same.
        tab20 = plt.get_cmap("tab20").colors
        colours = tab20[0::2] + tab20[1::2]
        for i, c in enumerate(cols):
            q = lib.split_unit(c)[0]
            ls = styles.get(q, "--" if ("dissipat" in q) else "-")
            lines += ax.plot(self.t, self.h.col(c) * f, ls=ls, color=colours[i % len(colours)], label=lib.humanize(q))
            self.used.add(c)
        ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
        self._time_axis(ax)
        ax.set_ylabel(lib.axis_label("Energy per unit thickness", u))
        lib.title_pair(ax, "Energies", self.run_title)
        err_cols = [n for n in self.h.names if "balance_error" in n]
        if err_cols:
            ax2 = ax.twinx()
            ax2.grid(False)
            ax2.spines["right"].set_visible(True)
            emax = max(float(np.nanmax(np.abs(self.h.col(c)))) if np.isfinite(self.h.col(c)).any() else 0.0
                       for c in err_cols)
            ex = math.floor(math.log10(emax)) if emax > 0 else 0
            ef = 10.0 ** (-ex) if -2 > ex or ex > 2 else 1.0
            for c in err_cols:
                lines += ax2.plot(self.t, self.h.col(c) * ef, color="0.15", lw=1.1, ls=":",
                                  label=lib.humanize(c) + " (right axis)")
                self.used.add(c)
            ax2.set_ylabel("Energy balance error" + (f" ($\\times 10^{{{ex}}}$)" if ef != 1.0 else " (–)"))
            lo, hi = ax2.get_ylim()
            ax2.set_ylim(min(0.0, lo), max(hi, 1e-12))
        if len(lines) > 4:  # many curves: legend under the plot, never over the data
            ax.legend(lines, [ln.get_label() for ln in lines], loc="upper center", bbox_to_anchor=(0.5, -0.13),
                      ncols=min(4, len(lines)), frameon=False)
        else:
            ax.legend(lines, [ln.get_label() for ln in lines], loc="best")
        self._stages(ax)
        self._save(fig, "energies.png")

    # ---------------------------------------------------------------- counts
    def counts(self, pattern: re.Pattern, fname: str, title: str):
        cols = [
            n
            for n in self.h.names
            if n not in self.used and pattern.search(n) and lib.split_unit(n)[1] == ""
        ]
        if not cols:
            return
        # Counts that never change (no joint ever broke, one fragment throughout, no
        # contact) say nothing: leave the figure out.
        if all(np.nanmin(self.h.col(c)) == np.nanmax(self.h.col(c)) for c in cols):
            self.used.update(cols)
            return
        fig, axes = plt.subplots(len(cols), 1, figsize=(9.5, 2.2 + 2.3 * len(cols)), sharex=True,
                                 layout="constrained", squeeze=False)
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for i, (ax, c) in enumerate(zip(axes[:, 0], cols)):
            y = self.h.col(c)
            label = lib.humanize(c)
            if np.isfinite(y).any():
                label += f": final {y[-1]:.0f}, max {np.nanmax(y):.0f}"
            ax.step(self.t, y, where="post", color=colors[i % len(colors)], label=label)
            ax.legend(loc="best")
            ax.set_ylabel(lib.humanize(c).capitalize())
            ax.set_ylim(bottom=0, top=max(1.0, float(np.nanmax(y)) * 1.08 if np.isfinite(y).any() else 1.0))
            ax.yaxis.get_major_locator().set_params(integer=True)
            self._stages(ax, labels=i == 0)
            self.used.add(c)
        self._time_axis(axes[-1, 0])
        lib.title_pair(axes[0, 0], title, self.run_title)
        self._save(fig, fname)

    # ---------------------------------------------------------------- loads
    def loads(self):
        cols = [
            n
            for n in self.h.names
            if n not in self.used and lib.split_unit(n)[1] in ("N/m", "N", "kN", "N/m²", "Pa")
            and (_LOAD.search(lib.split_unit(n)[0]) or lib.split_unit(n)[1] in ("N/m", "N"))
        ]
        if not cols:
            return
        by_unit: dict[str, list[str]] = {}
        for c in cols:
            by_unit.setdefault(lib.split_unit(c)[1], []).append(c)
        fig, axes = plt.subplots(len(by_unit), 1, figsize=(9.5, 1.5 + 3.5 * len(by_unit)), sharex=True,
                                 layout="constrained", squeeze=False)
        for i, (ax, (unit, cs)) in enumerate(zip(axes[:, 0], by_unit.items())):
            f, u = self._scaled([self.h.col(c) for c in cs], unit)
            for c in cs:
                y = self.h.col(c)
                label = lib.humanize(lib.split_unit(c)[0])
                if np.isfinite(y).any():
                    i = int(np.nanargmax(np.abs(y)))
                    label += f" (peak {y[i] * f:.4g} {u} at {self.t[i]:.3g} s)"
                ax.plot(self.t, y * f, label=label)
                self.used.add(c)
            ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
            ax.set_ylabel(lib.axis_label("Force per unit thickness" if unit == "N/m" else "Load", u))
            self._legend(ax, len(cs))
            self._stages(ax, labels=i == 0)
        self._time_axis(axes[-1, 0])
        lib.title_pair(axes[0, 0], "Loads and reactions", self.run_title)
        self._save(fig, "loads.png")
        self.load_displacement([c for cs in by_unit.values() for c in cs])

    def load_displacement(self, load_cols: list[str]):
        pairs = []
        for c in load_cols:
            q, unit = lib.split_unit(c)
            m = re.match(r"^(.*?)_(reaction|load|force)(?:_([xy]))?$", q)
            if not m:
                continue
            prefix, comp = m.group(1), m.group(3)
            cands = [f"{prefix}_displacement_{comp}_m"] if comp else []
            cands += [f"{prefix}_displacement_m"]
            for d in cands:
                if self.h.has(d):
                    pairs.append((c, d, unit))
                    self.used.add(d)
                    break
        if not pairs:
            return
        fig, ax = _fig(5.5)
        for c, d, unit in pairs:
            x, y = self.h.col(d), self.h.col(c)
            fx, ux = lib.autoscale(float(np.nanmax(np.abs(x))) if np.isfinite(x).any() else 0, "m")
            fy, uy = lib.autoscale(float(np.nanmax(np.abs(y))) if np.isfinite(y).any() else 0, unit)
            ax.plot(x * fx, y * fy, label=lib.humanize(lib.split_unit(c)[0]))
            ax.set_xlabel(lib.axis_label(lib.humanize(lib.split_unit(d)[0]).capitalize(), ux))
            ax.set_ylabel(lib.axis_label("Load", uy))
        ax.axhline(0, color="0.5", lw=0.8, zorder=0.5)
        lib.title_pair(ax, "Load–displacement", self.run_title)
        self._legend(ax, len(pairs))
        self._save(fig, "load_displacement.png")

    # ---------------------------------------------------------------- the rest
    def other(self):
        gauges = self.gauges()
        rest = []
        for n in self.h.names:
            if n in self.used:
                continue
            if any(n.startswith(g + "_acceleration_") for g in gauges):
                continue
            y = self.h.col(n)
            if not np.isfinite(y).any():
                continue
            rest.append(n)
        if not rest:
            return
        rest = rest[:12]
        ncols = 2 if len(rest) > 4 else 1
        nrows = math.ceil(len(rest) / ncols)
        fig, axes = plt.subplots(nrows, ncols, figsize=(9.5 if ncols == 1 else 12, 1.2 + 2.4 * nrows),
                                 sharex=True, layout="constrained", squeeze=False)
        for i, (ax, n) in enumerate(zip(axes.flat, rest)):
            q, unit = lib.split_unit(n)
            y = self.h.col(n)
            f, u = self._scaled([y], unit)
            ax.plot(self.t, y * f)
            ax.set_title(lib.axis_label(lib.humanize(q), u), fontsize=11, loc="left")
            self._stages(ax, labels=False)
        for ax in list(axes.flat)[len(rest):]:
            ax.set_visible(False)
        for ax in axes[-1, :]:
            self._time_axis(ax)
        fig.suptitle(f"Other histories — {self.run_title}", fontsize=13, fontweight="bold")
        self._save(fig, "other.png")

    def run(self) -> list[Path]:
        lib.setup_style()
        self.gauge_magnitude("displacement", "m", "m", "gauge_displacement.png", "Gauge displacement magnitude", "max")
        self.gauge_components()
        self.gauge_magnitude("velocity", "m_per_s", "m/s", "gauge_velocity.png", "Gauge velocity magnitude", "peak")
        self.gauge_magnitude("acceleration", "m_per_s2", "m/s²", "gauge_acceleration.png",
                             "Gauge acceleration magnitude", "peak")
        self.water()
        self.energies()
        self.counts(_COUNT_FRACTURE, "fracture.png", "Fracture")
        self.counts(_COUNT_CONTACT, "contacts.png", "Contacts")
        self.loads()
        self.other()
        return self.written


def make_plots(out: Path, show_stages: bool = True, quiet: bool = False) -> list[Path]:
    out = Path(out)
    if not out.is_dir():
        raise lib.InputError(f"{out}: no such output folder")
    return Plotter(out, show_stages, quiet).run()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Plot the histories of a dsdem run into OUT/plots/.")
    ap.add_argument("out", help="output folder of a dsdem run")
    ap.add_argument("--no-show-stages", action="store_true", help="do not mark stage changes")
    ap.add_argument("--quiet", action="store_true", help="print nothing but errors")
    a = ap.parse_args(argv)
    written = make_plots(Path(a.out), show_stages=not a.no_show_stages, quiet=a.quiet)
    if not a.quiet:
        if written:
            print(f"wrote {len(written)} plot(s):")
            for p in written:
                print(f"  {p}")
        else:
            print("no plots written: history.csv has no plottable columns")
    return 0


if __name__ == "__main__":
    lib.run_main(main)
