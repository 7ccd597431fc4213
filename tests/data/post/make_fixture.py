#!/usr/bin/env python3
"""Writes tests/data/post/fractured/: a tiny synthetic dsdem output folder with the files and
columns that later solver versions add (cracks.pvd, broken_joints, fragments, contacts,
fracture/contact energies, a plate reaction, two stages), so the post-processing commands
are tested on them before the solver writes them. Run with /usr/bin/python3 (needs meshio).

A 1.0 m x 0.2 m beam of 10 x 2 squares, each cut into two triangles with their own nodes
(zone A), glued by joints along every interior edge. Over three frames the joints under
mid-span damage, then break, and the right half drops and tilts.
"""
import json
from pathlib import Path

import meshio
import numpy as np

out = Path(__file__).resolve().parent / "fractured"
(out / "fields").mkdir(parents=True, exist_ok=True)
(out / "cracks").mkdir(parents=True, exist_ok=True)

nx, ny, L, H = 10, 2, 1.0, 0.2
hx, hy = L / nx, H / ny
pts, tris, mats = [], [], []
for j in range(ny):
    for i in range(nx):
        x0, y0 = i * hx, j * hy
        a, b, c, d = (x0, y0), (x0 + hx, y0), (x0 + hx, y0 + hy), (x0, y0 + hy)
        for t in ((a, b, c), (a, c, d)):
            base = len(pts)
            pts += list(t)
            tris.append([base, base + 1, base + 2])
            mats.append(0 if j == 0 else 1)
X = np.array(pts)
tris = np.array(tris)
mats = np.array(mats, dtype=np.int32)

# Joints: the interior edges (shared by two triangles), as segments in the reference frame.
edges = {}
for t, tri in enumerate(tris):
    for k in range(3):
        p, q = X[tri[k]], X[tri[(k + 1) % 3]]
        key = tuple(sorted([tuple(np.round(p, 9)), tuple(np.round(q, 9))]))
        edges.setdefault(key, []).append(t)
joints = [np.array(k) for k, ts in edges.items() if len(ts) == 2]
mid = np.array([j.mean(axis=0) for j in joints])
# The joints near mid-span (x = 0.5 m), damaging from the bottom up.
near = np.abs(mid[:, 0] - 0.5) < 1e-9

times = [0.0, 0.01, 0.02]
pvd_f, pvd_c = [], []
for n, t in enumerate(times):
    s = n / (len(times) - 1)
    # Triangle-wise: nodes of triangles whose centroid is right of mid-span move.
    u = np.zeros_like(X)
    cent = X[tris].mean(axis=1)
    for ti, tri in enumerate(tris):
        if cent[ti, 0] > 0.5:
            rel = X[tri] - np.array([0.5, 0.2])
            ang = -0.15 * s
            R = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
            u[tri] = rel @ R.T - rel + np.array([0.0, -0.02 * s])
    xy = X + u
    v = u / 0.01 if n else np.zeros_like(u)
    P3 = np.c_[xy, np.zeros(len(xy))]
    sig = np.c_[-1e5 * (1 + cent[:, 1]), 2e4 * np.sin(cent[:, 0] * 6), 1e4 * np.ones(len(tris))] * (1 + s)
    vm = np.sqrt(sig[:, 0] ** 2 - sig[:, 0] * sig[:, 1] + sig[:, 1] ** 2 + 3 * sig[:, 2] ** 2)
    m = meshio.Mesh(
        P3, [("triangle", tris)],
        point_data={"displacement_m": np.c_[u, np.zeros(len(u))], "velocity_m_per_s": np.c_[v, np.zeros(len(v))],
                    "acceleration_m_per_s2": np.zeros((len(u), 3))},
        cell_data={"stress_Pa": [sig], "von_mises_stress_Pa": [vm], "max_principal_stress_Pa": [sig[:, 1]],
                   "min_principal_stress_Pa": [sig[:, 0]], "group_id": [np.full(len(tris), 3, np.int32)],
                   "material_id": [mats], "zone": [np.zeros(len(tris), np.int32)]},
        field_data={"TimeValue": np.array([t])},
    )
    f = f"fields/fields_{n:06d}.vtu"
    meshio.write(out / f, m)
    pvd_f.append((t, f))
    # Cracks: segments at the current configuration (mean of the two faces' positions).
    segs = np.array(joints)
    state = np.zeros(len(joints), np.int32)
    damage = np.zeros(len(joints))
    damage[near] = [min(1.0, s * 1.5 * (1.2 - mid[k, 1] / H)) for k in np.nonzero(near)[0]]
    state[near & (damage >= 1.0)] = 1
    damage[state == 1] = 1.0
    segpts = segs.reshape(-1, 2)
    cells = np.arange(len(segpts)).reshape(-1, 2)
    cm = meshio.Mesh(np.c_[segpts, np.zeros(len(segpts))], [("line", cells)],
                     cell_data={"state": [state], "damage": [damage], "opening_m": [damage * 1e-3],
                                "slip_m": [damage * 1e-4], "mode": [np.where(damage > 0, 1, 0).astype(np.int32)],
                                "time_broken_s": [np.where(state == 1, t, -1.0)]},
                     field_data={"TimeValue": np.array([t])})
    c = f"cracks/cracks_{n:06d}.vtu"
    meshio.write(out / c, cm)
    pvd_c.append((t, c))


def pvd(entries):
    rows = "\n".join(f'    <DataSet timestep="{t!r}" group="" part="0" file="{f}"/>' for t, f in entries)
    return ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")


(out / "fields.pvd").write_text(pvd(pvd_f))
(out / "cracks.pvd").write_text(pvd(pvd_c))

# History: 41 rows, two stages (gravity settling, then loading).
t = np.linspace(0, 0.02, 41)
stage = (t > 0.005).astype(int)
load = np.where(t < 0.012, -4.0e5 * t / 0.012, -4.0e5 * np.exp(-(t - 0.012) / 0.002))
broken = np.floor(np.clip((t - 0.011) / 0.008, 0, 1) * 3).astype(int)
cols = {
    "time_s": t, "step": np.arange(len(t)) * 10, "stage": stage,
    "kinetic_J_per_m": 50 * t / 0.02, "strain_J_per_m": 1e3 * np.sin(t * 100) ** 2,
    "gravity_potential_J_per_m": -20 * t / 0.02, "external_work_J_per_m": 1.2e3 * t / 0.02,
    "damping_dissipated_J_per_m": 10 * t / 0.02, "fracture_dissipated_J_per_m": 30 * broken,
    "contact_energy_J_per_m": 5 * (t > 0.015),
    "energy_balance_error": 1e-3 * t / 0.02,
    "tip_displacement_x_m": 0.0 * t, "tip_displacement_y_m": -0.03 * (t / 0.02) ** 2,
    "tip_velocity_x_m_per_s": 0.0 * t, "tip_velocity_y_m_per_s": -3.0 * t,
    "tip_acceleration_x_m_per_s2": 0.0 * t, "tip_acceleration_y_m_per_s2": -150.0 + 0 * t,
    "broken_joints": broken, "fragments": 1 + (broken > 0), "contacts": 2 * (t > 0.015),
    "top_plate_displacement_y_m": -1e-4 * t / 0.02, "top_plate_reaction_y_N_per_m": load,
    "wall_clock_s": 3 * t / 0.02,
}
with open(out / "history.csv", "w") as f:
    f.write(",".join(cols) + "\n")
    for i in range(len(t)):
        f.write(",".join(repr(float(c[i])) if c.dtype.kind == "f" else str(int(c[i])) for c in cols.values()) + "\n")

(out / "dsdem.log").write_text(
    "[00:00:00] dsdem 0.1.0 (fixture), 1 threads\n"
    "[00:00:00] stage 1 'gravity': 0.005 s to t = 0.005 s\n"
    "[00:00:00] stage 2 'loading': 0.015 s to t = 0.02 s\n"
    "[00:00:01] done: 400 steps in 0.5 s\n")
(out / "scenario.yaml").write_text(
    "title: Fixture beam breaking at mid-span\n"
    "materials:\n  limestone: {E: 2.0e10, nu: 0.2, rho: 2600}\n  concrete: {E: 2.5e10, nu: 0.15, rho: 2300}\n"
    "output:\n  gauges:\n    - name: tip\n      at: [1.0, 0.2]\n")
summary = {
    "title": "Fixture beam breaking at mid-span", "scenario": "scenario.yaml", "dsdem_version": "0.1.0 (fixture)",
    "elements": int(len(tris)), "nodes": int(len(X)), "joints": int(len(joints)), "steps": 400,
    "dt_s": 5e-05, "end_time_s": 0.02, "threads": 1, "wall_time_s": 0.5, "energy_balance_error": 0.001,
    "broken_joints": 3, "fragments": 2, "peak_load_N_per_m": -4.0e5,
    "final_energies": {"unit": "J_per_m", "kinetic": 50.0, "strain": 12.3, "fracture_dissipated": 90.0},
    "gauges": [{"name": "tip", "max_displacement_m": 0.03, "peak_velocity_mps": 0.15,
                "time_of_peak_velocity_s": 0.02, "final_displacement_m": [0.0, -0.03]}],
}
(out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
print(f"wrote {out}")
