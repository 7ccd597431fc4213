"""The moving (SPH) water of a dsdem run, for render_fields, plot_history and report.

OUT/water.pvd lists OUT/water/water_NNNNNN.vtu: one vertex per particle with point data
velocity_m_per_s, pressure_Pa, density_kg_per_m3, particle_id. history.csv has the water's
measurements by name (run/water_watch.cpp): <gauge>_eta_m, wave_amplitude_m,
<bank>_runup_m, <crest>_overtopped_m2_per_m, <curve>_force_x/_y_<unit>,
<curve>_peak_pressure_Pa, water_energy_gain_<unit>, moving_water_work_<unit>.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import dsdem_plotlib as lib

# What colours the particles: (label, unit) by the --water choice.
WATER_VALUES = {"speed": ("Water speed", "m/s"), "pressure": ("Water pressure", "Pa")}


def water_frames(out: Path) -> list[lib.Frame]:
    """The water frames of a run, in order; [] for a run without moving water."""
    return lib.read_pvd(out / "water.pvd") or lib.glob_frames(out / "water", "water")


def read_water_frame(path: Path, what: str) -> tuple[np.ndarray, np.ndarray]:
    """(positions (n, 2), value per particle (n,)) of one water VTU, float32; `what` is
    speed (|v|) or pressure."""
    import meshio

    try:
        m = meshio.read(str(path))
    except Exception as e:  # noqa: BLE001
        raise lib.InputError(f"{path}: cannot read ({e})") from e
    xy = np.asarray(m.points, dtype=np.float64)[:, :2]
    if what == "pressure":
        v = m.point_data.get("pressure_Pa")
        if v is None:
            raise lib.InputError(f"{path}: no pressure_Pa point data (use --water speed)")
        vals = np.asarray(v, dtype=np.float64).reshape(-1)
    else:
        v = m.point_data.get("velocity_m_per_s")
        if v is None:
            raise lib.InputError(f"{path}: no velocity_m_per_s point data (use --water pressure)")
        v = np.asarray(v, dtype=np.float64)
        vals = np.hypot(v[:, 0], v[:, 1])
    return xy.astype(np.float32), vals.astype(np.float32)


def _typical_gap(times: list[float]) -> float:
    ts = np.unique(np.array([t for t in times if math.isfinite(t)]))
    return float(np.median(np.diff(ts))) if ts.size >= 2 else 0.0


def match_by_time(field: list[tuple[int, float]], water: list[lib.Frame]) -> dict[int, lib.Frame]:
    """Field frame number -> the water frame of the same moment: the nearest in time, within
    half the typical frame interval of either series (the two share the field interval, so
    they normally coincide). Without times (no .pvd), by frame number."""
    if not water:
        return {}
    out: dict[int, lib.Frame] = {}
    timed = [w for w in water if math.isfinite(w.time)]
    wt = np.array([w.time for w in timed])
    tol = 0.5 * max(_typical_gap([t for _, t in field]), _typical_gap(list(wt))) + 1e-9
    by_num = {w.number: w for w in water}
    for num, t in field:
        if math.isfinite(t) and wt.size:
            i = int(np.argmin(np.abs(wt - t)))
            if abs(wt[i] - t) <= tol * (1 + 1e-9) + 1e-12 * abs(t):
                out[num] = timed[i]
        elif not math.isfinite(t) and num in by_num:
            out[num] = by_num[num]
    return out


def particle_spacing(summary: dict, xy: np.ndarray | None) -> float:
    """The particle spacing dp (m): summary.json moving_water.spacing_m, else the square
    root of the area per particle of the water's bounding box."""
    mw = summary.get("moving_water") if isinstance(summary, dict) else None
    if isinstance(mw, dict) and isinstance(mw.get("spacing_m"), (int, float)) and mw["spacing_m"] > 0:
        return float(mw["spacing_m"])
    if xy is None or len(xy) < 2:
        return 0.0
    span = np.ptp(xy, axis=0)
    return float(math.sqrt(max(span[0] * span[1], 1e-30) / len(xy)))


def gauge_positions(scenario: dict) -> dict[str, float]:
    """Free-surface gauge name -> x (m), from the scenario's reservoir.sph.gauges."""
    sph = ((scenario.get("reservoir") or {}).get("sph") or {}) if isinstance(scenario, dict) else {}
    out = {}
    for g in sph.get("gauges") or [] if isinstance(sph, dict) else []:
        try:
            out[str(g["name"])] = float(g["x"])
        except (KeyError, TypeError, ValueError):
            continue
    return out


@dataclass
class WaterColumns:
    """history.csv columns of the moving water, by role."""

    gauges: list[tuple[str, str]] = field(default_factory=list)   # (gauge, column) of eta
    amplitude: str | None = None
    runup: list[tuple[str, str]] = field(default_factory=list)    # (bank, column)
    crests: list[tuple[str, str]] = field(default_factory=list)   # (crest, column)
    forces: list[tuple[str, str, str]] = field(default_factory=list)  # (curve, x column, y column)
    pressures: list[tuple[str, str]] = field(default_factory=list)    # (curve, column)

    def all(self) -> list[str]:
        cols = [c for _, c in self.gauges + self.runup + self.crests + self.pressures]
        cols += [c for _, x, y in self.forces for c in (x, y)]
        return cols + ([self.amplitude] if self.amplitude else [])

    def __bool__(self) -> bool:
        return bool(self.gauges or self.amplitude or self.runup or self.crests or self.forces)


def water_columns(names: list[str]) -> WaterColumns:
    """The moving water's columns among a history's column names."""
    w = WaterColumns()
    have = set(names)
    for n in names:
        if m := re.fullmatch(r"(.+)_eta_m", n):
            w.gauges.append((m.group(1), n))
        elif n == "wave_amplitude_m":
            w.amplitude = n
        elif m := re.fullmatch(r"(.+)_runup_m", n):
            w.runup.append((m.group(1), n))
        elif m := re.fullmatch(r"(.+)_overtopped_m2_per_m", n):
            w.crests.append((m.group(1), n))
        elif m := re.fullmatch(r"(.+)_peak_pressure_Pa", n):
            w.pressures.append((m.group(1), n))
        elif m := re.fullmatch(r"(.+)_force_x_(N_per_m|N)", n):
            y = f"{m.group(1)}_force_y_{m.group(2)}"
            if y in have:
                w.forces.append((m.group(1), n, y))
    return w
