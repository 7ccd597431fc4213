"""Shared helpers of the validation scripts: read a dsdem output folder.

Only numpy, meshio and matplotlib (Agg). Every reader takes the output folder OUT of
`dsdem run ... -o OUT`.
"""
from __future__ import annotations

import json
import os
import re
import xml.etree.ElementTree as ET

import numpy as np


def read_history(out: str) -> dict[str, np.ndarray]:
    """OUT/history.csv as a dict of columns (names as in the header, with units)."""
    path = os.path.join(out, "history.csv")
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header)}


def column(hist: dict[str, np.ndarray], prefix: str) -> np.ndarray:
    """The column whose name starts with prefix (units differ: N_per_m or N)."""
    for name, values in hist.items():
        if name.startswith(prefix):
            return values
    raise KeyError(f"no history column starts with '{prefix}'; columns: {', '.join(hist)}")


def column_name(hist: dict[str, np.ndarray], prefix: str) -> str:
    for name in hist:
        if name.startswith(prefix):
            return name
    raise KeyError(prefix)


def read_cracks(out: str) -> list[dict]:
    """OUT/cracks.csv: broken joints in order of breaking."""
    path = os.path.join(out, "cracks.csv")
    rows = []
    if not os.path.exists(path):
        return rows
    with open(path) as f:
        header = f.readline().strip().split(",")
        for line in f:
            v = line.rstrip("\n").split(",")
            r = dict(zip(header, v))
            r["joint"] = int(r["joint"])
            for k in ("time_s", "x_m", "y_m"):
                r[k] = float(r[k])
            rows.append(r)
    return rows


def read_pvd(out: str, name: str) -> list[tuple[float, str]]:
    """(time, file) of each frame of OUT/<name>.pvd."""
    path = os.path.join(out, name + ".pvd")
    if not os.path.exists(path):
        return []
    root = ET.parse(path).getroot()
    frames = []
    for ds in root.iter("DataSet"):
        frames.append((float(ds.get("timestep")), os.path.join(out, ds.get("file"))))
    frames.sort()
    return frames


def read_summary(out: str) -> dict:
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def load_scenario(out: str, scenario: str | None) -> dict:
    """The scenario YAML (given, or the one named in OUT/summary.json)."""
    import yaml

    path = scenario
    if path is None:
        path = read_summary(out).get("scenario")
    if path is None or not os.path.exists(path):
        raise SystemExit(f"scenario file not found ({path}); pass --scenario")
    with open(path) as f:
        return yaml.safe_load(f)


def frame_nearest(frames: list[tuple[float, str]], t: float) -> tuple[float, str]:
    return min(frames, key=lambda f: abs(f[0] - t))


def frame_before(frames: list[tuple[float, str]], t: float) -> tuple[float, str] | None:
    before = [f for f in frames if f[0] <= t]
    return before[-1] if before else None


def frame_after(frames: list[tuple[float, str]], t: float) -> tuple[float, str] | None:
    after = [f for f in frames if f[0] >= t]
    return after[0] if after else None


class Fields:
    """One frame of OUT/fields/*.vtu: triangles in the current configuration."""

    def __init__(self, path: str):
        import meshio

        m = meshio.read(path)
        self.x = m.points[:, :2]
        self.tri = m.cells_dict["triangle"]
        self.u = m.point_data["displacement_m"][:, :2]
        self.X = self.x - self.u  # reference positions
        cd = {k: v[0] for k, v in m.cell_data.items()}
        self.stress = cd["stress_Pa"]  # xx, yy, xy
        self.zone = cd["zone"].astype(int)
        self.group = cd["group_id"].astype(int)
        self.fragment = cd["fragment"].astype(int) if "fragment" in cd else None
        p0, p1, p2 = (self.X[self.tri[:, k]] for k in range(3))
        self.area0 = 0.5 * np.abs((p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0]))
        self.centroid0 = (p0 + p1 + p2) / 3.0
        c0, c1, c2 = (self.x[self.tri[:, k]] for k in range(3))
        self.centroid = (c0 + c1 + c2) / 3.0

    def pieces(self, mask: np.ndarray) -> np.ndarray:
        """Reference areas of the fragments among the triangles in mask, largest first."""
        if self.fragment is None:
            raise SystemExit("the fields VTU has no 'fragment' cell field (dsdem older than the validation branch)")
        labels = self.fragment[mask]
        areas = np.bincount(labels, weights=self.area0[mask])
        areas = areas[areas > 0]
        return np.sort(areas)[::-1]


def read_segments(path: str) -> dict[str, np.ndarray]:
    """One frame of OUT/cracks/*.vtu: joint segments (current positions) and their data."""
    import meshio

    m = meshio.read(path)
    seg = m.cells_dict["line"]
    out = {"a": m.points[seg[:, 0], :2], "b": m.points[seg[:, 1], :2]}
    for k, v in m.cell_data.items():
        out[re.sub(r"_(m|s|Pa)$", "", k)] = v[0]
    return out


def _plain(o):
    """numpy scalars and arrays as plain JSON values."""
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"{type(o).__name__} is not JSON serializable")


def write_json(path: str, data: dict) -> None:
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=2, sort_keys=False, default=_plain)
        f.write("\n")


def merge_summary(out: str, keys: dict, renamed: dict | None = None) -> None:
    """Merge a case's keys into OUT/summary.json, keeping the runner's keys: the file is
    read, updated and written to a temporary file in the same folder, then renamed over it
    (atomic: a reader never sees half a file). renamed: runner keys that the case
    redefines, kept under a new name ({old: new}); running it twice is safe."""
    import tempfile

    path = os.path.join(out, "summary.json")
    with open(path) as f:
        data = json.load(f)
    for old, new in (renamed or {}).items():
        if old in data and new not in data:
            data[new] = data[old]
    data.update(keys)
    fd, tmp = tempfile.mkstemp(prefix=".summary.", suffix=".json", dir=out)
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(data, f, indent=2, default=_plain)
            f.write("\n")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def failure_shares(seg: dict, joints: list[int], ft: float, GI: float, c: float, GII: float,
                   kn: float | None = None) -> np.ndarray:
    """Share of the opening in the failure criterion (eq. 9) of broken joints: en^2 /
    (en^2 + es^2) with en = <dn - wt>/wn, es = <|ds| - ws>/wsII from the opening and slip
    at failure (a broken joint's separations stay frozen at their failure values in the
    crack frames). wsII = 2 GII / c (no compression); wt, ws ~ 0 beside wn, wsII unless
    kn is given. 1 = pure tension, 0 = pure shear."""
    wn = 2 * GI / ft
    wsII = 2 * GII / c
    wt = ft / kn if kn else 0.0
    ws = c / kn if kn else 0.0
    dn = seg["opening"][joints]
    ds = np.abs(seg["slip"][joints])
    en = np.maximum(dn - wt, 0) / wn
    es = np.maximum(ds - ws, 0) / wsII
    tot = en * en + es * es
    return np.where(tot > 0, en * en / np.where(tot > 0, tot, 1), 0.5)
