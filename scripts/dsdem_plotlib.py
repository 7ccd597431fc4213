"""Shared helpers of the dsdem post-processing scripts (plot_history, render_fields, report).

Everything here reads a dsdem output folder (OUT/) by file and column *names*, never by
position, so new columns and files written by later solver versions are picked up or
skipped without breaking anything.

Column and key naming convention (io/atomic_file.hpp, name_with_unit): the SI unit is the
last part of the name, e.g. ``kinetic_J_per_m``, ``crest_velocity_x_m_per_s``,
``dt_s``, ``peak_velocity_mps``; names without a unit suffix are dimensionless or counts.
"""

from __future__ import annotations

import json
import math
import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # headless: no X server, ever

import numpy as np  # noqa: E402

# Exit codes shared with the C++ side: 0 ok, 1 unexpected failure, 2 bad input.
EXIT_INPUT = 2


class InputError(Exception):
    """Bad input (missing file, unknown field, malformed option): exit code 2."""


# `dsdem render --field` names and the VTU arrays they stand for, in a plane and a 3D run
# (render_fields.py and render_fields3d.py add their own stress components).
FIELD_ALIASES = {
    "velocity": "velocity_m_per_s",
    "displacement": "displacement_m",
    "acceleration": "acceleration_m_per_s2",
    "stress": "von_mises_stress_Pa",
    "von_mises": "von_mises_stress_Pa",
    "material": "material_id",
    "max_principal": "max_principal_stress_Pa",
    "min_principal": "min_principal_stress_Pa",
    "sxx": "stress_Pa:xx",
    "syy": "stress_Pa:yy",
    "sxy": "stress_Pa:xy",
}


def fail(message: str, code: int = EXIT_INPUT) -> None:
    print(f"error: {message}", file=sys.stderr)
    sys.exit(code)


def run_main(main) -> None:
    """Run a script's main(), turning InputError into a clean message and exit code 2."""
    try:
        sys.exit(main())
    except InputError as e:
        fail(str(e))
    except KeyboardInterrupt:
        sys.exit(130)


# --------------------------------------------------------------------------------------
# Units from names
# --------------------------------------------------------------------------------------

# Unit suffixes, longest first: (suffix tokens joined by "_", pretty unit).
_UNIT_SUFFIXES = [
    ("kg_per_m3", "kg/m³"),
    ("J_per_m2", "J/m²"),
    ("N_per_m2", "N/m²"),
    ("m_per_s2", "m/s²"),
    ("J_per_m", "J/m"),
    ("kg_per_m", "kg/m"),
    ("N_per_m", "N/m"),
    ("W_per_m", "W/m"),
    ("N_per_m3", "N/m³"),
    ("m_per_s", "m/s"),
    ("per_s", "1/s"),
    ("mps2", "m/s²"),
    ("mps", "m/s"),
    ("Pa", "Pa"),
    ("kPa", "kPa"),
    ("MPa", "MPa"),
    ("deg", "°"),
    ("rad", "rad"),
    ("Hz", "Hz"),
    ("kg", "kg"),
    ("m2", "m²"),
    ("m3", "m³"),
    ("J", "J"),
    ("N", "N"),
    ("W", "W"),
    ("m", "m"),
    ("s", "s"),
    ("g", "g"),
]
_UNIT_SUFFIXES.sort(key=lambda p: -len(p[0].split("_")))


def split_unit(name: str) -> tuple[str, str]:
    """'crest_velocity_x_m_per_s' -> ('crest_velocity_x', 'm/s'); 'broken_joints' -> ('broken_joints', '')."""
    tokens = name.split("_")
    for suffix, pretty in _UNIT_SUFFIXES:
        st = suffix.split("_")
        if len(tokens) > len(st) and tokens[-len(st):] == st:
            return "_".join(tokens[: -len(st)]), pretty
    return name, ""


def humanize(quantity: str) -> str:
    """'damping_dissipated' -> 'damping dissipated'."""
    return quantity.replace("_", " ").strip()


# SI prefixes for axis scaling, so a 0.0011 m displacement reads 1.1 mm and a 3e11 J/m
# energy reads 300 GJ/m.
_FORCE_LIKE = ("J", "N", "Pa", "W")


def autoscale(max_abs: float, unit: str) -> tuple[float, str]:
    """Return (factor, unit label) so that values * factor read naturally in `unit`."""
    if not unit or not math.isfinite(max_abs) or max_abs <= 0:
        return 1.0, unit
    head = re.match(r"^(Pa|J|N|W|m)(?=$|/|²|³)", unit)
    if not head:
        return 1.0, unit
    sym = head.group(1)
    rest = unit[len(sym):]
    if sym in _FORCE_LIKE:
        prefixes = [("", 0), ("k", 3), ("M", 6), ("G", 9), ("T", 12)]
    else:  # lengths: µm, mm, m (a run-out is never quoted in km here)
        if rest.startswith("²") or rest.startswith("³"):
            return 1.0, unit
        prefixes = [("µ", -6), ("m", -3), ("", 0)]
    chosen = prefixes[0]
    for p in prefixes:
        if max_abs >= 10 ** p[1] * 0.9999:
            chosen = p
    return 10.0 ** (-chosen[1]), chosen[0] + sym + rest


def axis_label(quantity: str, unit: str) -> str:
    return f"{quantity} ({unit})" if unit else quantity


# --------------------------------------------------------------------------------------
# Number formatting
# --------------------------------------------------------------------------------------


def fmt_num(v, digits: int = 4) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return str(v)
        if v == 0:
            return "0"
        a = abs(v)
        if 1e-3 <= a < 1e6:
            # Fixed point with `digits` significant digits, but never rounding away integer
            # digits: 15277.18 -> "15277", 1.0233 -> "1.023", 0.0010883 -> "0.001088".
            decimals = max(0, digits - 1 - math.floor(math.log10(a)))
            s = f"{v:.{decimals}f}"
            if "." in s:
                s = s.rstrip("0").rstrip(".")
            return s
        return f"{v:.{digits - 1}e}"
    if isinstance(v, (list, tuple)):
        return "(" + ", ".join(fmt_num(x, digits) for x in v) + ")"
    return str(v)


# --------------------------------------------------------------------------------------
# Output folder
# --------------------------------------------------------------------------------------


@dataclass
class History:
    names: list[str]
    data: np.ndarray  # rows x columns

    def has(self, name: str) -> bool:
        return name in self.index

    def col(self, name: str) -> np.ndarray:
        return self.data[:, self.index[name]]

    @property
    def index(self) -> dict[str, int]:
        return {n: i for i, n in enumerate(self.names)}

    @property
    def time(self) -> np.ndarray:
        return self.col("time_s")


def read_history(path: Path) -> History:
    """history.csv -> History. Tolerates a truncated last line (a run killed mid-write)."""
    if not path.is_file():
        raise InputError(f"{path}: not found")
    with open(path, "r", encoding="utf-8", errors="replace") as f:
        header = f.readline().strip()
        if not header:
            raise InputError(f"{path}: empty file (no header row)")
        names = [h.strip() for h in header.split(",")]
        body = f.read()
    lines = body.splitlines()
    ncol = len(names)
    rows = []
    bad = 0
    try:
        data = np.loadtxt(lines, delimiter=",", ndmin=2, dtype=float) if lines else np.empty((0, ncol))
        if data.shape[1] != ncol:
            raise ValueError
    except ValueError:
        for ln in lines:
            parts = ln.split(",")
            if len(parts) != ncol:
                bad += 1
                continue
            try:
                rows.append([float(p) if p.strip() else math.nan for p in parts])
            except ValueError:
                bad += 1
        data = np.array(rows, dtype=float).reshape(-1, ncol)
        if bad:
            print(f"warning: {path}: skipped {bad} malformed row(s)", file=sys.stderr)
    if "time_s" not in names:
        raise InputError(f"{path}: no 'time_s' column (is this a dsdem history file?)")
    return History(names, data)


def read_summary(out: Path) -> dict:
    p = out / "summary.json"
    if not p.is_file():
        return {}
    try:
        with open(p, "r", encoding="utf-8") as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        print(f"warning: {p}: cannot read ({e})", file=sys.stderr)
        return {}


def stage_names(out: Path) -> dict[int, str]:
    """Stage names from dsdem.log lines "stage 1 'main': ..." -> {0: 'main'} (the history's
    stage column counts from 0, the log from 1)."""
    names: dict[int, str] = {}
    p = out / "dsdem.log"
    if not p.is_file():
        return names
    try:
        with open(p, "r", encoding="utf-8", errors="replace") as f:
            for line in f:
                m = re.search(r"\bstage (\d+) '([^']*)'", line)
                if m:
                    names.setdefault(int(m.group(1)) - 1, m.group(2))
    except OSError:
        pass
    return names


def find_scenario(out: Path, summary: dict) -> Path | None:
    """The scenario YAML of a run: the path recorded in summary.json (absolute, relative to
    the working directory, or relative to the folder holding OUT), else a YAML copy in OUT."""
    cands: list[Path] = []
    s = summary.get("scenario")
    if isinstance(s, str) and s:
        p = Path(s)
        if p.is_absolute():
            cands.append(p)
        else:
            cands += [Path.cwd() / p, out.parent / p, out / p, out / p.name]
    cands += sorted(out.glob("*.yaml")) + sorted(out.glob("*.yml"))
    for c in cands:
        if c.is_file():
            return c
    return None


def load_yaml(path: Path | None) -> dict:
    if path is None:
        return {}
    try:
        import yaml  # optional

        with open(path, "r", encoding="utf-8") as f:
            d = yaml.safe_load(f)
        return d if isinstance(d, dict) else {}
    except Exception:  # noqa: BLE001 - optional nicety: names of materials and gauges
        return {}


def material_names(summary: dict, scenario: dict) -> dict[int, str]:
    """material_id -> name. summary.json 'materials' (list of names or of {name}) wins;
    otherwise the scenario's materials sorted by name (the solver keeps them in a
    std::map, so ids follow byte order of the names)."""
    mats = summary.get("materials")
    if isinstance(mats, list) and mats:
        out = {}
        for i, m in enumerate(mats):
            if isinstance(m, str):
                out[i] = m
            elif isinstance(m, dict) and "name" in m:
                out[int(m.get("id", i))] = str(m["name"])
        if out:
            return out
    sm = scenario.get("materials")
    if isinstance(sm, dict) and sm:
        return {i: str(n) for i, n in enumerate(sorted(sm.keys(), key=lambda s: str(s).encode()))}
    return {}


@dataclass
class Frame:
    number: int
    time: float
    path: Path


def read_pvd(pvd: Path) -> list[Frame]:
    """Frames of a ParaView collection, in time order. Missing files are skipped with a warning."""
    if not pvd.is_file():
        return []
    try:
        root = ET.parse(pvd).getroot()
    except ET.ParseError as e:
        raise InputError(f"{pvd}: not a valid PVD file ({e})") from e
    frames = []
    missing = 0
    for i, ds in enumerate(root.iter("DataSet")):
        f = ds.get("file")
        if not f:
            continue
        path = (pvd.parent / f).resolve()
        if not path.is_file():
            missing += 1
            continue
        m = re.search(r"_(\d+)\.vtu$", f)
        num = int(m.group(1)) if m else i
        try:
            t = float(ds.get("timestep", "nan"))
        except ValueError:
            t = math.nan
        frames.append(Frame(num, t, path))
    if missing:
        print(f"warning: {pvd}: {missing} listed file(s) missing, skipped", file=sys.stderr)
    frames.sort(key=lambda fr: (fr.number, fr.time))
    return frames


def glob_frames(folder: Path, stem: str) -> list[Frame]:
    """Fallback when the .pvd index is missing: OUT/<stem>/<stem>_NNNNNN.vtu, time unknown."""
    frames = []
    for p in sorted(folder.glob(f"{stem}_*.vtu")):
        m = re.search(r"_(\d+)\.vtu$", p.name)
        if m:
            frames.append(Frame(int(m.group(1)), math.nan, p))
    return frames


# --------------------------------------------------------------------------------------
# Figure style
# --------------------------------------------------------------------------------------


def setup_style() -> None:
    import matplotlib.pyplot as plt

    plt.rcParams.update(
        {
            "figure.dpi": 100,
            "savefig.dpi": 130,
            "font.size": 11,
            "axes.titlesize": 13,
            "axes.titleweight": "bold",
            "axes.labelsize": 12,
            "xtick.labelsize": 10.5,
            "ytick.labelsize": 10.5,
            "legend.fontsize": 10,
            "legend.framealpha": 0.9,
            "axes.grid": True,
            "grid.alpha": 0.3,
            "grid.linestyle": "-",
            "axes.spines.top": False,
            "axes.spines.right": False,
            "lines.linewidth": 1.6,
            "axes.prop_cycle": matplotlib.cycler(color=matplotlib.colormaps["tab10"].colors),
            "axes.formatter.limits": (-4, 5),
            "axes.formatter.use_mathtext": True,
        }
    )


def title_pair(ax, main: str, run_title: str | None) -> None:
    """Bold plot title on the left, the run's title in small grey on the right."""
    ax.set_title(main, loc="left")
    if run_title:
        t = run_title if len(run_title) <= 60 else run_title[:57] + "..."
        ax.set_title(t, loc="right", fontsize=9.5, color="0.4", fontweight="normal")
