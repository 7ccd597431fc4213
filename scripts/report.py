#!/usr/bin/env python3
"""dsdem report: one self-contained HTML page OUT/report.html summarising a run.

    report.py OUT [--no-render] [--quiet]

Contents: title and scenario, key results, the reservoir wave (a run with moving water: the
computed wave beside the Heller & Hager estimate, run-up, overtopping, forces, their plots;
a dry run with a reservoir: the Heller & Hager estimate), model, gauge table, history plots (made with
plot_history first if OUT/plots is missing or older than history.csv), the last field
snapshot (rendered with render_fields if none exists, unless --no-render), every scalar of
summary.json with its unit, the scenario YAML, run information and the log. Images are
embedded as base64: the file can be mailed or archived on its own, no external links.

A 3D run (summary.json "dimension": 3) has no gauges, joints, run-out or water: its key results
are the largest displacement (and where), the largest speed, the energy balance; its snapshot is
the last frame twice, the model's outer surface in perspective and the section through it
(render_fields3d.py).
"""

from __future__ import annotations

import argparse
import base64
import datetime as _dt
import html
import math
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dsdem_plotlib as lib  # noqa: E402
import dsdem_water as wat  # noqa: E402
import numpy as np  # noqa: E402

PLOT_ORDER = [
    ("gauge_displacement.png", "Gauge displacement magnitude"),
    ("gauge_velocity.png", "Gauge velocity magnitude"),
    ("gauge_displacement_components.png", "Gauge displacement components"),
    ("gauge_acceleration.png", "Gauge acceleration magnitude"),
    ("energies.png", "Energies and energy balance"),
    ("fracture.png", "Fracture: broken joints and fragments"),
    ("contacts.png", "Contacts"),
    ("loads.png", "Loads and reactions"),
    ("load_displacement.png", "Load–displacement"),
    ("other.png", "Other histories"),
]
# The moving water's plots, shown in the reservoir wave section rather than with the histories.
WATER_PLOTS = [
    ("water_surface.png", "Free-surface elevation above the still level at the gauges"),
    ("wave_amplitude.png", "Wave amplitude over the reservoir (the highest surface above the still level at each "
                           "moment) and its envelope, the largest so far"),
    ("wave_decay.png", "The wave at the gauges against their distance from the slide's entry, beside Heller & "
                       "Hager's 2D decay of the wave height H(x) = (3/4) (P (x/h)^(-1/3))^(4/5) h"),
    ("water_runup.png", "Run-up (the highest water on each bank) and the water past each crest"),
    ("water_forces.png", "Force of the water on the named curves, and the peak pressure on them"),
]
MODEL_KEYS = ["elements", "nodes", "joints", "steps", "dt_s", "dt_controlled_by", "dt_adaptive", "dt_last_s",
              "dt_last_controlled_by", "end_time_s"]
RUN_KEYS = ["dsdem_version", "threads", "wall_time_s", "element_steps_per_s"]

CSS = """
:root { --fg:#1d2327; --muted:#5f6b73; --line:#dde3e8; --accent:#1f5f99; --bg:#ffffff; --soft:#f5f7f9; }
* { box-sizing: border-box; }
body { margin:0; background:var(--soft); color:var(--fg);
  font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
main { max-width: 1180px; margin: 0 auto; padding: 28px 32px 48px; background: var(--bg);
  box-shadow: 0 0 0 1px var(--line); min-height: 100vh; }
header { border-bottom: 3px solid var(--accent); padding-bottom: 14px; margin-bottom: 22px; }
h1 { margin: 0 0 6px; font-size: 28px; }
h3 { margin: 22px 0 8px; font-size: 16px; }
h2 { margin: 34px 0 12px; font-size: 20px; color: var(--accent); border-bottom: 1px solid var(--line);
  padding-bottom: 4px; }
.sub { color: var(--muted); font-size: 14px; }
.sub code { background: var(--soft); padding: 1px 5px; border-radius: 3px; }
nav { font-size: 14px; margin-top: 10px; }
nav a { color: var(--accent); margin-right: 14px; text-decoration: none; }
.cards { display: grid; grid-template-columns: repeat(auto-fill, minmax(200px, 1fr)); gap: 12px; }
.card { border: 1px solid var(--line); border-radius: 6px; padding: 10px 14px; background: var(--soft); }
.card .v { font-size: 22px; font-weight: 600; }
.card .k { color: var(--muted); font-size: 13px; }
table { border-collapse: collapse; width: 100%; margin: 6px 0 10px; font-size: 14px; }
th, td { text-align: left; padding: 6px 10px; border-bottom: 1px solid var(--line); vertical-align: top; }
th { background: var(--soft); font-weight: 600; }
td.num { font-variant-numeric: tabular-nums; text-align: right; white-space: nowrap; }
th.num { text-align: right; }
table.kv td:first-child { color: var(--muted); width: 38%; }
tr:hover td { background: #fafbfc; }
figure { margin: 16px 0 26px; }
figure img { max-width: 100%; height: auto; border: 1px solid var(--line); border-radius: 4px; display: block; }
figcaption { color: var(--muted); font-size: 13.5px; margin-top: 6px; }
pre { background: #f7f8fa; border: 1px solid var(--line); border-radius: 4px; padding: 12px 14px;
  overflow-x: auto; font: 13px/1.45 ui-monospace, "SF Mono", Menlo, Consolas, monospace; }
details summary { cursor: pointer; color: var(--accent); margin: 6px 0; }
.note { color: var(--muted); font-style: italic; }
footer { margin-top: 40px; color: var(--muted); font-size: 12.5px; border-top: 1px solid var(--line);
  padding-top: 10px; }
@media print { body { background: white; } main { box-shadow: none; } details { display: none; } }
"""


def esc(x) -> str:
    return html.escape(str(x), quote=True)


def key_label(key: str) -> tuple[str, str]:
    q, unit = lib.split_unit(key)
    return lib.humanize(q), unit


def img_tag(path: Path, alt: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{esc(alt)}">'


def value_cell(v) -> str:
    if v is None:  # null in summary.json: not measured (a wave period with fewer than two crests)
        return _num(None)
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return f'<td class="num">{esc(lib.fmt_num(v))}</td>'
    if isinstance(v, list) and all(isinstance(x, (int, float)) for x in v):
        return f'<td class="num">{esc(lib.fmt_num(v))}</td>'
    return f"<td>{esc(lib.fmt_num(v) if not isinstance(v, str) else v)}</td>"


def kv_table(rows: list[tuple[str, str, object]]) -> str:
    out = ['<table class="kv"><tbody>']
    for label, unit, v in rows:
        out.append(f"<tr><td>{esc(label)}{(' (' + esc(unit) + ')') if unit else ''}</td>{value_cell(v)}</tr>")
    out.append("</tbody></table>")
    return "\n".join(out)


def flatten_scalars(d: dict, prefix: str = "", unit_hint: str = "") -> list[tuple[str, str, object]]:
    """All scalar (and short numeric list) values of summary.json with their units.
    A nested object with a "unit" key gives that unit to its members (final_energies)."""
    rows = []
    for k, v in d.items():
        if isinstance(v, dict):
            hint = lib.split_unit("x_" + v["unit"])[1] if isinstance(v.get("unit"), str) else ""
            if not hint and isinstance(v.get("unit"), str):
                hint = v["unit"]
            q, u = lib.split_unit(k)  # max_runup_m: {bank: value} -> "max runup: bank (m)"
            rows += flatten_scalars({kk: vv for kk, vv in v.items() if kk != "unit"},
                                    f"{prefix}{lib.humanize(q if u else k)}: ", hint or u)
        elif isinstance(v, list):
            if v and all(isinstance(x, (int, float)) for x in v) and len(v) <= 6:
                label, unit = key_label(k)
                rows.append((prefix + label, unit or unit_hint, v))
        else:
            label, unit = key_label(k)
            rows.append((prefix + label, unit or unit_hint, v))
    return rows


def dict_list_table(items: list[dict], first: str = "name") -> str:
    keys: list[str] = []
    for it in items:
        for k in it:
            if k not in keys:
                keys.append(k)
    if first in keys:
        keys.remove(first)
        keys.insert(0, first)
    head = []
    for k in keys:
        label, unit = key_label(k)
        cls = "" if k == first else ' class="num"'
        head.append(f"<th{cls}>{esc(label)}{(' (' + esc(unit) + ')') if unit else ''}</th>")
    rows = []
    for it in items:
        cells = []
        for k in keys:
            v = it.get(k, "")
            cells.append(value_cell(v) if k != first else f"<td><b>{esc(v)}</b></td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{''.join(head)}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def key_cards(summary: dict, max_speed: float | None = None) -> str:
    """The key results as cards; max_speed: a 3D run's largest node speed from history.csv."""
    cards = []

    def card(value: str, label: str):
        cards.append(f'<div class="card"><div class="v">{esc(value)}</div><div class="k">{esc(label)}</div></div>')

    def scaled(v: float, unit: str) -> str:
        f, u = lib.autoscale(abs(v), unit)
        return f"{v * f:.3g} {u}"

    gauges = [g for g in summary.get("gauges", []) if isinstance(g, dict)]
    disp = [(g.get("max_displacement_m"), g.get("name", "?")) for g in gauges
            if isinstance(g.get("max_displacement_m"), (int, float))]
    if disp:
        v, n = max(disp)
        card(scaled(v, "m"), f"largest gauge displacement ({n})")
        card(scaled(sum(d for d, _ in disp) / len(disp), "m"), "mean of the gauges' max displacement")
    vel = [(g.get("peak_velocity_mps"), g.get("name", "?"), g.get("time_of_peak_velocity_s")) for g in gauges
           if isinstance(g.get("peak_velocity_mps"), (int, float))]
    if vel:
        v, n, t = max(vel, key=lambda x: x[0])
        # dr2_postprocess.py counts the gauges' times from the earthquake's start (and keeps the
        # runner's, from the run's start, as gauges_from_run_start); every other time is the run's.
        origin = "the earthquake's start" if "gauges_from_run_start" in summary else "the run's start"
        when = f" at {t:.3g} s from {origin}" if isinstance(t, (int, float)) else ""
        card(scaled(v, "m/s"), f"peak gauge velocity ({n}{when})")
    if isinstance(summary.get("max_wave_amplitude_m"), (int, float)):
        card(scaled(summary["max_wave_amplitude_m"], "m"), "max wave amplitude (moving water)")
    runups = [(v, n) for n, v in (summary.get("max_runup_m") or {}).items() if isinstance(v, (int, float))]
    if runups:
        v, n = max(runups)
        card(scaled(v, "m"), f"highest run-up above the reservoir level ({n})")
    for k in ("broken_joints", "fragments"):
        if isinstance(summary.get(k), (int, float)):
            card(lib.fmt_num(summary[k]), lib.humanize(k))
    for k, v in summary.items():
        if re.search(r"(blocked|blockage|runout|run_out|travel)", k) and isinstance(v, (int, float)):
            label, unit = key_label(k)
            card(f"{lib.fmt_num(v, 3)} {unit}".strip(), label)
    umax = summary.get("max_displacement")
    if isinstance(umax, dict) and isinstance(umax.get("value_m"), (int, float)):  # a 3D run's largest
        at = umax.get("at_m")
        where = (f" (at x, y, z = {', '.join(f'{c:.4g}' for c in at)} m)"
                 if isinstance(at, list) and all(isinstance(c, (int, float)) for c in at) else "")
        card(scaled(umax["value_m"], "m"), f"largest displacement{where}")
    if isinstance(max_speed, (int, float)) and math.isfinite(max_speed):
        card(scaled(max_speed, "m/s"), "largest speed of any node (history.csv)")
    if isinstance(summary.get("end_time_s"), (int, float)):
        card(f"{summary['end_time_s']:.4g} s", "simulated time")
    if isinstance(summary.get("energy_balance_error"), (int, float)):
        card(f"{summary['energy_balance_error']:.2e}", "energy balance error")
    return f'<div class="cards">{"".join(cards)}</div>' if cards else ""


def stability_section(out: Path, summary: dict) -> str:
    """The output of `dsdem stability` (docs/theory.md §9): FS, displacement against F, the mechanism."""
    if "factor_of_safety" not in summary:
        return ""
    rows = [("factor of safety (static)", "", summary["factor_of_safety"])]
    if "factor_of_safety_pseudo_static" in summary:
        rows.append(("factor of safety (pseudo-static)", "", summary["factor_of_safety_pseudo_static"]))
    if "factor_of_safety_dynamic" in summary:
        rows.append(("factor of safety (dynamic: survives the earthquake)", "", summary["factor_of_safety_dynamic"]))
    for variant, b in (summary.get("brackets") or {}).items():
        name = variant.replace("_", "-")
        rows.append((f"{name}: highest F that stood", "", b.get("stood")))
        rows.append((f"{name}: lowest F that failed", "", b.get("failed")))
        if b.get("undecided"):
            rows.append((f"{name}: undecided between them (FS may lie up to the lowest F that failed)", "",
                         ", ".join(f"{F:.4f}" for F in b["undecided"])))
        c = b.get("budget_check")
        if isinstance(c, dict):
            held = "held" if c.get("stood_held") and c.get("failed_held", True) else "DID NOT HOLD"
            rows.append((f"{name}: bracketing verdicts watched twice as long", "", held))
    st = summary.get("settings") or {}
    if "window_steps" in st:
        rows.append(("trials: observation window", "steps", st["window_steps"]))
        rows.append(("trials: slope period (window)", "s", st.get("period_s")))
        rows.append(("trials: step budget", "steps", st.get("max_steps")))
    body = kv_table(rows)
    trials = summary.get("trials") or []
    if trials:
        trs = [[f"<td>{esc(t.get('variant', '').replace('_', '-'))}{' (budget check)' if t.get('budget_check') else ''}</td>",
                _num(t.get("F")), f"<td>{esc(t.get('result'))}</td>",
                f"<td>{esc(t.get('reason'))}{(' (' + esc(t['note']) + ')') if t.get('note') else ''}</td>",
                _num(t.get("steps")), _num(t.get("max_displacement_m")), _num(t.get("unbalanced_ratio"))]
               for t in trials]
        body += _table(["trial", "F", "result", "why", "steps", "max displacement (m)", "unbalanced ratio"], trs)
    for name, cap in (("fs_displacement.png", "Largest displacement against the strength-reduction factor F"),
                      ("stability_trials.png", "Each trial's unbalanced force ratio and monitored displacement"),
                      ("mechanism.png", "The mechanism at the lowest F that failed (static)"),
                      ("mechanism_pseudo_static.png", "The mechanism at the lowest F that failed (pseudo-static)")):
        p = out / name
        if p.is_file():
            body += f"<figure>{img_tag(p, cap)}<figcaption>{esc(cap)} (<code>{esc(name)}</code>)</figcaption></figure>"
    return body


def impulse_wave_section(summary: dict) -> str:
    """The slide where it entered the reservoir and the Heller & Hager (2010) wave (docs/theory.md §12)."""
    h = summary.get("heller_hager")
    if not isinstance(h, dict):
        return ""
    if h.get("applicable") is False:  # water alone: nothing enters the water
        return (kv_table([("reservoir level", "m", h.get("still_level_m"))]) +
                f'<p class="note">Not applicable: {esc(h.get("reason") or "no slide")}.</p>')
    rows = [("reservoir level", "m", h.get("still_level_m")), ("water depth", "m", h.get("depth_m")),
            ("bank slope", "deg", h.get("bank_slope_deg"))]
    if not h.get("slide_entered_water"):
        return kv_table(rows) + '<p class="note">The slide did not enter the reservoir in this run.</p>'
    rows += [("impact time", "s", h.get("impact_time_s")), ("slide speed", "m/s", h.get("slide_speed_mps")),
             ("slide thickness", "m", h.get("slide_thickness_m")),
             ("slide mass", "kg/m", h.get("slide_mass_kg_per_m")),
             ("impulse product parameter P", "", h.get("impulse_product")),
             ("maximum wave amplitude a_M", "m", h.get("amplitude_m")),
             ("maximum wave height H_M", "m", h.get("height_m")),
             ("distance of H_M from the impact", "m", h.get("distance_of_max_height_m"))]
    body = kv_table(rows)
    outside = h.get("outside_validity") or []
    if outside:
        items = ", ".join(f"{esc(o['parameter'])} = {o['value']:.3g} (range {o['min']:g}-{o['max']:g})" for o in outside)
        body += f'<p class="note">Outside the range of Heller &amp; Hager\'s experiments: {items}. ' \
                'The estimate is an extrapolation.</p>'
    return body


def _num(v) -> str:
    return f'<td class="num">{esc(lib.fmt_num(v))}</td>' if isinstance(v, (int, float)) else '<td class="num">–</td>'


def _table(head: list[str], rows: list[list[str]]) -> str:
    """A table from header labels and rows of ready <td> cells."""
    num = ' class="num"'
    th = "".join(f"<th{num if i else ''}>{esc(h)}</th>" for i, h in enumerate(head))
    return f"<table><thead><tr>{th}</tr></thead><tbody>" + "".join(
        "<tr>" + "".join(r) + "</tr>" for r in rows) + "</tbody></table>"


def _by_prefix(d: dict, prefix: str):
    """The value of the first key starting with prefix (energies carry their unit: _J_per_m or _J)."""
    for k, v in d.items():
        if k.startswith(prefix):
            return v
    return None


def heller_hager_missing(h) -> str:
    """Why there is no Heller & Hager estimate to compare with, or "" when there is one."""
    if not isinstance(h, dict):
        return "summary.json has no heller_hager block, so there is no Heller &amp; Hager estimate to compare with."
    if h.get("applicable") is False:
        return (f"Water alone ({esc(h.get('reason') or 'no slide')}): there is no Heller &amp; Hager estimate "
                "to compare with.")
    if not h.get("slide_entered_water"):
        return ("The slide did not enter the reservoir during the run, so there is no Heller &amp; Hager estimate "
                "(it needs the slide's speed, thickness and mass where it enters the water).")
    if not isinstance(h.get("amplitude_m"), (int, float)):
        return ("The slide reached the water with no mass moving faster than 0.5 m/s, so there is no "
                "Heller &amp; Hager estimate.")
    return ""


def gauge_wave(out: Path, after: float | None, overrun: dict) -> dict[str, tuple[float, float]]:
    """Highest and lowest free surface at each gauge (from history.csv; after the slide's entry when known, before
    the slide's rock reached the gauge's surface: summary.json moving_water.slide_at_gauges_s)."""
    try:
        h = lib.read_history(out / "history.csv")
    except lib.InputError:
        return {}
    res = {}
    for g, c in wat.water_columns(h.names).gauges:
        keep = h.time >= after if isinstance(after, (int, float)) else np.ones(h.time.shape, bool)
        if isinstance(overrun.get(g), (int, float)):
            keep = keep & (h.time < overrun[g])
        y = h.col(c)[keep]
        y = y[np.isfinite(y)]
        if y.size:
            res[g] = (float(y.max()), float(y.min()))
    return res


def primary_height(h) -> tuple[float | None, str | None, float | None]:
    """The largest primary wave (first crest to the trough after it) among the gauges beyond the shoreline:
    its height, gauge and distance from the shoreline."""
    waves = [(g["height_m"], g.get("name"), g.get("distance_m")) for g in (h.get("gauges") or [])
             if isinstance(g, dict) and isinstance(g.get("height_m"), (int, float))] if isinstance(h, dict) else []
    return max(waves, key=lambda w: w[0], default=(None, None, None))


def wave_comparison(mw: dict, h) -> str:
    """The computed wave beside Heller & Hager's estimate, and the validity verdict."""
    peak = mw.get("max_wave_amplitude") or {}
    a = peak.get("amplitude_m")
    missing = heller_hager_missing(h)
    hh = {} if missing else h
    # H as Heller & Hager measure it: one wave's crest to its trough (the gauges' highest and
    # lowest over the whole record would add the drawdown and the basin's sloshing).
    height, height_gauge, dist = primary_height(hh)

    def ratio(c, e):
        return _num(c / e) if isinstance(c, (int, float)) and isinstance(e, (int, float)) and e else _num(None)

    rows = [["<td>maximum wave amplitude a_M (m): computed, the highest water above the still level beyond the "
             "slide's front</td>", _num(a), _num(hh.get("amplitude_m")), ratio(a, hh.get("amplitude_m"))],
            ["<td>maximum wave height H_M (m): computed, the largest primary wave (first crest to the trough after "
             f"it) at a gauge beyond the shoreline{f' ({esc(height_gauge)})' if height_gauge else ''}</td>",
             _num(height), _num(hh.get("height_m")), ratio(height, hh.get("height_m"))],
            ["<td>distance of H_M from the shoreline (m): computed, its gauge's; Heller &amp; Hager, x_M</td>",
             _num(dist), _num(hh.get("distance_of_max_height_m")), _num(None)]]
    body = _table(["", "computed (moving water)", "Heller & Hager (2010)", "computed / Heller & Hager"], rows)
    if missing:
        return body + f'<p class="note">{missing}</p>'
    if height is None:
        body += ('<p class="note">No gauge beyond the shoreline saw a whole primary wave (the trough after its first '
                 'crest) before the run ended: no computed H_M. Gauges nearer the slide, or a longer run, give it.</p>')
    outside = h.get("outside_validity") or []
    if h.get("inside_validity") and not outside:
        body += ('<p><b>Inside the range of Heller &amp; Hager\'s experiments</b> (slide Froude number, relative '
                 'thickness and mass, impulse product, slope): the estimate applies.</p>')
    else:
        items = ", ".join(f"{esc(o['parameter'])} = {o['value']:.3g} (range {o['min']:g}-{o['max']:g})"
                          for o in outside)
        body += f"<p><b>Outside the range of Heller &amp; Hager's experiments</b>: {items or 'see inputs'}. " \
                "The estimate is an extrapolation.</p>"
    return body


def wave_along_reservoir(h) -> str:
    """The primary wave at each gauge beyond the shoreline against Heller & Hager's 2D decay laws."""
    gauges = h.get("gauges") if isinstance(h, dict) and not heller_hager_missing(h) else None
    if not gauges:
        return ""
    onset = h.get("decay_onset_relative_distance")
    rows = []
    for g in gauges:
        rows.append([f"<td><b>{esc(g['name'])}</b></td>", _num(g.get("relative_distance")), _num(g.get("crest_m")),
                     _num(g.get("heller_hager_crest_m")), _num(g.get("crest_ratio")), _num(g.get("height_m")),
                     _num(g.get("heller_hager_height_m")), _num(g.get("height_ratio")),
                     _num(g.get("slide_at_gauge_s"))])
    body = _table(["gauge", "x / h from the shoreline", "first crest (m)", "Heller & Hager a(x) (m)", "ratio",
                   "crest to trough (m)", "Heller & Hager H(x) (m)", "ratio", "slide's rock at its surface from (s)"], rows)
    note = ("The primary wave at each gauge after the slide's entry and before the slide's rock rose to within two "
            "spacings of the surface there: its first crest above the still level and the trough after it (a dash: "
            "not seen before the run ended or the debris reached the gauge). Heller &amp; Hager's decay laws a(x) = 3/5 "
            "(P (x/h)^-1/3)^4/5 h and H(x) = 3/4 (...) h")
    if isinstance(onset, (int, float)):
        note += (f" meet a_M and H_M at x / h = {lib.fmt_num(onset)}; nearer the shoreline they exceed their own "
                 "maxima, a_M and H_M, which bound the wave there")
    return body + f'<p class="note">{note}.</p>'


def water_measurements(mw: dict, level, gauges: dict[str, tuple[float, float]], since: str) -> str:
    """Where and when the wave peaked, run-up, overtopping, forces, gauges and energy."""
    peak = mw.get("max_wave_amplitude") or {}
    body = kv_table([("maximum wave amplitude", "m", peak.get("amplitude_m")), ("where: x", "m", peak.get("x_m")),
                     ("when", "s", peak.get("time_s"))])
    runup = mw.get("runup") or {}
    if runup:
        body += _table(["bank", "highest water (m)", "above the reservoir level (m)", "at rest against it (m)",
                        "rise above its rest (m)", "at (s)"],
                       [[f"<td><b>{esc(n)}</b></td>", _num(r.get("elevation_m")),
                         _num(r["elevation_m"] - level if isinstance(r.get("elevation_m"), (int, float))
                              and isinstance(level, (int, float)) else None), _num(r.get("at_rest_elevation_m")),
                         _num(r.get("rise_m")), _num(r.get("time_s"))]
                        for n, r in runup.items()])
        late = [n for n, r in runup.items() if r.get("peak_at_end_of_run")]
        if late:
            body += (f'<p class="note">The run-up on {", ".join(esc(n) for n in late)} was highest at the run\'s last '
                     "row: the water may still have been rising there (a wave that has not reached the bank leaves "
                     "only the water at rest); a longer run would tell.</p>")
    crests = mw.get("overtopping") or {}
    if crests:
        body += _table(["crest", "water past it (m²/m)", "at (s)"],
                       [[f"<td><b>{esc(n)}</b></td>", _num(c.get("volume_m2_per_m")), _num(c.get("time_s"))]
                        for n, c in crests.items()])
    forces = mw.get("force_on_curves") or {}
    if forces:
        body += _table(["curve", "largest force (N/m)", "at (s)", "at rest (N/m)", "peak pressure (Pa)"],
                       [[f"<td><b>{esc(n)}</b></td>", _num(_by_prefix(f, "max_force")), _num(f.get("time_s")),
                         _num(_by_prefix(f, "at_rest_force")), _num(f.get("peak_pressure_Pa"))]
                        for n, f in forces.items()])
    periods = mw.get("wave_period_s") or {}
    names = list(dict.fromkeys(list(gauges) + list(periods)))
    if names:
        rows = []
        for n in names:
            hi, lo = gauges.get(n, (None, None))
            T = periods.get(n)
            rows.append([f"<td><b>{esc(n)}</b></td>", _num(hi), _num(lo),
                         _num(T) if isinstance(T, (int, float)) else '<td class="num">fewer than two crests</td>'])
        body += _table(["gauge", f"highest surface{since} (m)", f"lowest surface{since} (m)", "wave period (s)"], rows)
    gain, ke = _by_prefix(mw, "energy_gain"), _by_prefix(mw, "slide_kinetic_energy_at_impact")
    flow, top = mw.get("flow_speed") or {}, mw.get("max_speed") or {}
    if flow or top:
        body += kv_table([("flow speed (1 % of the water faster; weakly compressible below c0 / 10)", "m/s",
                           flow.get("speed_mps")), ("sound speed c0", "m/s", mw.get("sound_speed_mps")),
                          ("fastest particle", "m/s", top.get("speed_mps")), ("where: x", "m", top.get("x_m")),
                          ("when", "s", top.get("time_s"))])
    body += kv_table([("energy handed to the water (its largest gain)", "J/m", gain),
                      ("slide's kinetic energy where it entered", "J/m", ke),
                      ("ratio of the two (above 1 when the slide goes on descending into the water after its "
                       "entry)", "", mw.get("energy_handed_to_water_ratio")),
                      ("work of the water on the solid", "J/m", _by_prefix(mw, "moving_water_work")),
                      ("work of the walls' own pressure on the water (modified boundary: no wall state stores "
                       "it; energy the wall model put in)", "J/m", _by_prefix(mw, "boundary_work"))])
    return body


def first_taken_out(t: float) -> str:
    """When the first water particle was taken out: the run's time, or in the settle before step 0."""
    if t < 0:
        return f", the first in the settle, {lib.fmt_num(-t)} s before step 0"
    return f", the first at t = {lib.fmt_num(t)} s"


def reservoir_wave_section(out: Path, summary: dict, plots: list[Path]) -> str:
    """A run with moving water (docs/theory.md §11, §12): the wave it computed beside Heller & Hager's estimate."""
    mw = summary.get("moving_water")
    if not isinstance(mw, dict):
        return ""
    h = summary.get("heller_hager")
    level = h.get("still_level_m") if isinstance(h, dict) else None
    after = h.get("impact_time_s") if isinstance(h, dict) else None
    gauges = gauge_wave(out, after, mw.get("slide_at_gauges_s") or {})
    parts = [f'<p class="sub">Moving water (SPH): {esc(lib.fmt_num(mw.get("particles", "?")))} particles '
             f'{esc(lib.fmt_num(mw.get("spacing_m", "?")))} m apart, {esc(lib.fmt_num(mw.get("depth_m", "?")))} m deep'
             + (f", reservoir level {esc(lib.fmt_num(level))} m" if isinstance(level, (int, float)) else "")
             + (f"; settled, the water stood at {esc(lib.fmt_num(mw['still_level_m']))} m "
                + ("at step 0 (water alone: no slide) " if isinstance(h, dict) and h.get("applicable") is False
                   else "before the slide met it ")
                + "(the still level the wave's amplitude and the primary waves at the gauges are measured from; the "
                "gauges' highest and lowest surface and the run-up are given above the reservoir level)"
                if isinstance(mw.get("still_level_m"), (int, float)) else "") + ".</p>"]
    if isinstance(mw.get("escaped_particles"), int) and mw["escaped_particles"] > 0:
        parts.append(f'<p class="note">{mw["escaped_particles"]} particles left the model (a gap in the solid): '
                     "the water's measurements miss them.</p>")
    ex = mw.get("excluded") or {}
    if isinstance(ex.get("particles"), int) and ex["particles"] > 0:
        first = ex.get("first") or {}
        parts.append(f'<p class="note">{ex["particles"]} water particles '
                     f'({lib.fmt_num(100.0 * ex.get("fraction", 0.0))} % of the water) left its weakly compressible '
                     "range (faster than its sound speed, or its density off by half: spray flung out of a squeeze) "
                     "and were taken out of the water"
                     + (first_taken_out(first.get("time_s")) if isinstance(first.get("time_s"), (int, float)) else "")
                     + "; the log names them (the first twenty one by one).</p>")
    peak = mw.get("max_wave_amplitude") or {}
    peak_t = peak.get("time_s")
    end = summary.get("end_time_s")
    if isinstance(peak_t, (int, float)) and isinstance(end, (int, float)) and peak_t >= 0.98 * end:
        parts.append(f'<p class="note">The largest amplitude came at the end of the run ({lib.fmt_num(peak_t)} s of '
                     f"{lib.fmt_num(end)} s): the wave may still have been growing; a longer run would tell.</p>")
    a = peak.get("amplitude_m")
    if peak.get("at_wall") is True and isinstance(a, (int, float)) and a > 0:
        parts.append('<p class="note">The largest amplitude stands against a wall (the water\'s edge at rest is '
                     "vertical there): it is the wave's reflection, up to twice the incident wave, the height the "
                     "wall sees; the travelling wave is read at the gauges and in the primary waves below.</p>")
    if isinstance(a, (int, float)) and a <= 0:
        parts.append('<p class="note">The water\'s surface never rose above the still level in the reservoir '
                     f"(largest amplitude {lib.fmt_num(a)} m): no wave was measured.</p>")
    parts.append("<h3>The wave against Heller &amp; Hager (2010)</h3>" + wave_comparison(mw, h)
                 + wave_along_reservoir(h))
    since = " after the slide's entry" if isinstance(after, (int, float)) else ""
    if any(isinstance(t, (int, float)) for t in (mw.get("slide_at_gauges_s") or {}).values()):
        since += " until the slide's rock reached its surface"
    parts.append("<h3>Measurements</h3>" + water_measurements(mw, level, gauges, since))
    by_name = {p.name: p for p in plots}
    for name, cap in WATER_PLOTS:
        if name in by_name:
            parts.append(f"<figure>{img_tag(by_name[name], cap)}<figcaption>{esc(cap)} "
                         f"(<code>plots/{esc(name)}</code>)</figcaption></figure>")
    if isinstance(h, dict):
        parts.append("<details><summary>Heller &amp; Hager inputs (the slide where it entered)</summary>"
                     + impulse_wave_section(summary) + "</details>")
    return "\n".join(parts)


def ensure_plots(out: Path, quiet: bool) -> list[Path]:
    hist = out / "history.csv"
    plots = out / "plots"
    pngs = sorted(plots.glob("*.png")) if plots.is_dir() else []
    stale = hist.is_file() and pngs and min(p.stat().st_mtime for p in pngs) < hist.stat().st_mtime
    if hist.is_file() and (not pngs or stale):
        import plot_history

        try:
            plot_history.make_plots(out, quiet=True)
        except lib.InputError as e:
            print(f"warning: no plots: {e}", file=sys.stderr)
        pngs = sorted(plots.glob("*.png")) if plots.is_dir() else []
    pngs = [p for p in pngs if not p.name.endswith(".tmp.png")]
    order = {name: i for i, (name, _) in enumerate(PLOT_ORDER)}
    return sorted(pngs, key=lambda p: (order.get(p.name, len(order)), p.name))


def png_text(path: Path) -> dict[str, str]:
    """The tEXt chunks of a PNG (render_fields3d.py writes the frame's time and section there)."""
    import struct
    import zlib

    out: dict[str, str] = {}
    try:
        data = path.read_bytes()
    except OSError:
        return out
    pos = 8
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"tEXt" and b"\0" in body:
            k, v = body.split(b"\0", 1)
            out[k.decode("latin-1")] = v.decode("latin-1")
        elif kind == b"zTXt" and b"\0" in body:
            k, v = body.split(b"\0", 1)
            try:
                out[k.decode("latin-1")] = zlib.decompress(v[1:]).decode("latin-1")
            except zlib.error:
                pass
        elif kind in (b"IDAT", b"IEND"):
            break  # the text chunks come before the picture
        pos += 12 + length
    return out


def section_of(snap: Path | None) -> Path | None:
    """The section of a 3D snapshot's frame (<field>_section_NNNNNN.png beside <field>_NNNNNN.png)."""
    m = re.match(r"^(.*)_(\d{6})\.png$", snap.name) if snap is not None else None
    if m is None:
        return None
    p = snap.with_name(f"{m.group(1)}_section_{m.group(2)}.png")
    return p if p.is_file() else None


def latest_snapshot(out: Path, allow_render: bool, quiet: bool) -> Path | None:
    def find():
        best = None
        for p in (out / "render").glob("*_[0-9][0-9][0-9][0-9][0-9][0-9].png") if (out / "render").is_dir() else []:
            m = re.match(r"^(.*)_(\d{6})\.png$", p.name)
            if not m or p.name.endswith(".tmp.png") or m.group(1).endswith("_section"):
                continue
            rank = (int(m.group(2)), m.group(1) == "velocity", p.stat().st_mtime)
            if best is None or rank > best[0]:
                best = (rank, p)
        return best[1] if best else None

    snap = find()
    if snap is None and allow_render and ((out / "fields.pvd").is_file() or (out / "fields").is_dir()):
        import render_fields

        try:
            render_fields.main([str(out), "--frames", "last", "--quiet", "--jobs", "1"])
        except (lib.InputError, SystemExit, Exception) as e:  # noqa: BLE001 - the report goes on without it
            print(f"warning: no snapshot rendered: {e}", file=sys.stderr)
        snap = find()
    return snap


def build(out: Path, allow_render: bool, quiet: bool) -> Path:
    summary = lib.read_summary(out)
    if not summary:
        raise lib.InputError(f"{out / 'summary.json'}: not found or unreadable")
    three_d = summary.get("dimension") == 3
    max_speed = None
    if three_d:  # the history's largest speed: a key number of a 3D run, which has no gauges
        try:
            h = lib.read_history(out / "history.csv")
            if h.has("max_speed_m_per_s") and h.data.shape[0]:
                max_speed = float(np.nanmax(h.col("max_speed_m_per_s")))
        except lib.InputError:
            pass
    title = str(summary.get("title") or out.name)
    scen_path = lib.find_scenario(out, summary)
    scenario_name = str(summary.get("scenario", "")) or (str(scen_path) if scen_path else "")
    plots = ensure_plots(out, quiet)
    snap = latest_snapshot(out, allow_render, quiet)
    now = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")

    sec: list[str] = []
    nav: list[tuple[str, str]] = []

    def section(anchor: str, heading: str, body: str):
        if body:
            nav.append((anchor, heading))
            sec.append(f'<section id="{anchor}"><h2>{esc(heading)}</h2>\n{body}\n</section>')

    section("key", "Key results", key_cards(summary, max_speed))
    section("stability", "Factor of safety", stability_section(out, summary))
    if isinstance(summary.get("moving_water"), dict):
        section("reservoir-wave", "Reservoir wave", reservoir_wave_section(out, summary, plots))
    else:  # a dry reservoir: the estimate only
        section("wave", "Impulse wave (Heller & Hager estimate)", impulse_wave_section(summary))

    model_rows = [("model", "", "3D, linear tetrahedra")] if three_d else []
    for k in MODEL_KEYS:
        if k in summary:
            label, unit = key_label(k)
            model_rows.append(("tetrahedra" if three_d and k == "elements" else label, unit, summary[k]))
    section("model", "Model", kv_table(model_rows) if model_rows else "")

    gauges = [g for g in summary.get("gauges", []) if isinstance(g, dict)]
    section("gauges", "Gauges", dict_list_table(gauges) if gauges else "")

    if "factor_of_safety" in summary:  # dsdem stability: no histories
        plots = []
    if plots:
        figs = []
        captions = dict(PLOT_ORDER)
        water_pngs = {n for n, _ in WATER_PLOTS} if isinstance(summary.get("moving_water"), dict) else set()
        for p in (p for p in plots if p.name not in water_pngs):
            cap = captions.get(p.name, lib.humanize(p.stem).capitalize())
            figs.append(f"<figure>{img_tag(p, cap)}<figcaption>{esc(cap)} (<code>plots/{esc(p.name)}</code>)"
                        f"</figcaption></figure>")
        section("plots", "Histories", "\n".join(figs))
    elif "factor_of_safety" not in summary:
        section("plots", "Histories", '<p class="note">No history plots (history.csv missing or empty).</p>')

    if snap is not None:
        m = re.match(r"^(.*)_(\d{6})\.png$", snap.name)
        cap = f"{lib.humanize(m.group(1)).capitalize()} field, frame {int(m.group(2))}" if m else snap.name
        cut = section_of(snap)
        if three_d:
            cap += ": the model's outer surface in perspective"
        body = (f"<figure>{img_tag(snap, cap)}<figcaption>{esc(cap)} (<code>render/{esc(snap.name)}</code>). "
                f"More: <code>dsdem render {esc(out)} --movie</code></figcaption></figure>")
        if cut is not None:
            plane = png_text(cut).get("dsdem:section")
            ccap = (f"{lib.humanize(m.group(1)).capitalize()} field, frame {int(m.group(2))}: the section"
                    + (f" {plane}" if plane else "") + ", the model behind the plane, its cut face showing the "
                    "field inside")
            body += (f"<figure>{img_tag(cut, ccap)}<figcaption>{esc(ccap)} (<code>render/{esc(cut.name)}</code>). "
                     f"Another plane: <code>dsdem render {esc(out)} --section x=...</code></figcaption></figure>")
        section("snapshot", "Snapshot", body)

    # Every scalar of summary.json (minus what the sections above show as tables).
    scalars = flatten_scalars({k: v for k, v in summary.items() if k not in ("gauges", "title", "scenario")})
    section("summary", "All results (summary.json)", kv_table(scalars))
    for k, v in summary.items():
        if k != "gauges" and isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            section(f"list-{esc(k)}", lib.humanize(k).capitalize(), dict_list_table(v))

    if scen_path is not None:
        try:
            text = scen_path.read_text(encoding="utf-8", errors="replace")
            sets = [o for o in summary.get("overrides") or [] if isinstance(o, str)]
            applied = ("<p><b>Run with these overrides</b> of the file (<code>--set</code>, applied in this order; "
                       "the values below are the file's):</p><pre>" + esc("\n".join(sets)) + "</pre>") if sets else ""
            section("parameters", "Parameters (scenario)",
                    f'<p class="sub">From <code>{esc(scen_path)}</code></p>{applied}<pre>{esc(text)}</pre>')
        except OSError:
            pass
    else:
        section("parameters", "Parameters (scenario)",
                f'<p class="note">The scenario file <code>{esc(scenario_name)}</code> was not found '
                f"from here; its values are not shown.</p>")

    run_rows = []
    for k in RUN_KEYS:
        if k in summary:
            label, unit = key_label(k)
            run_rows.append((label.replace("dsdem version", "dsdem version"), unit, summary[k]))
    run_rows.append(("output folder", "", str(out.resolve())))
    run_rows.append(("report generated", "", now))
    log = out / "dsdem.log"
    log_html = ""
    if log.is_file():
        text = log.read_text(encoding="utf-8", errors="replace")
        lines = text.splitlines()
        if len(lines) > 400:
            text = "\n".join(lines[:100] + [f"... ({len(lines) - 300} lines) ..."] + lines[-200:])
        log_html = f"<details><summary>Log (dsdem.log)</summary><pre>{esc(text)}</pre></details>"
    section("run", "Run information", kv_table(run_rows) + log_html)

    version = summary.get("dsdem_version", "")
    head_sub = []
    if scenario_name:
        head_sub.append(f"scenario <code>{esc(scenario_name)}</code>")
    if version:
        head_sub.append(f"dsdem {esc(version)}")
    head_sub.append(f"report of {esc(now)}")
    footer = ("dsdem: continuous–discontinuous simulation (FEM-DSDEM) of rock-slope failure and landslide run-out, "
              + ("3D continuum (linear tetrahedra). Values in SI units; energies in J." if three_d else
                 "2D.\nValues in SI units per metre of thickness unless stated."))
    page = f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="dsdem report">
<title>{esc(title)} — dsdem report</title>
<style>{CSS}</style>
</head>
<body>
<main>
<header>
<h1>{esc(title)}</h1>
<div class="sub">{' &middot; '.join(head_sub)}</div>
<nav>{''.join(f'<a href="#{a}">{esc(h)}</a>' for a, h in nav)}</nav>
</header>
{chr(10).join(sec)}
<footer>{footer}</footer>
</main>
</body>
</html>
"""
    path = out / "report.html"
    tmp = out / "report.html.tmp"
    tmp.write_text(page, encoding="utf-8")
    tmp.replace(path)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Write OUT/report.html, a self-contained report of a dsdem run.")
    ap.add_argument("out", help="output folder of a dsdem run")
    ap.add_argument("--no-render", action="store_true", help="do not render a field snapshot when none exists")
    ap.add_argument("--quiet", action="store_true", help="print nothing but errors")
    a = ap.parse_args(argv)
    out = Path(a.out)
    if not out.is_dir():
        raise lib.InputError(f"{out}: no such output folder")
    path = build(out, allow_render=not a.no_render, quiet=a.quiet)
    if not a.quiet:
        print(f"wrote {path} ({path.stat().st_size / 1024:.0f} KiB)")
    return 0


if __name__ == "__main__":
    lib.run_main(main)
