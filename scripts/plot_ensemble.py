#!/usr/bin/env python3
"""dsdem ensemble: plots and one self-contained HTML page OUT/report.html of an ensemble.

    plot_ensemble.py OUT [--quiet]

Reads OUT/ensemble.json, OUT/members.csv, OUT/envelopes.csv (and OUT/deposit_hazard.csv)
written by `dsdem ensemble` and writes OUT/plots/:

  distributions.png   histogram and exceedance curve P(X >= x) of the main outputs
  events.png          event probabilities with their 95 % Wilson intervals
  envelopes.png       P5-P95 band and P50 over time of each gauge and of the kinetic energy
  tornado.png         Spearman rank correlation of the main outputs with each varied value
  convergence.png     mean, P50 and event probabilities against the number of members
  deposit_hazard.png  P(debris thicker than d) along x (when the members have a deposit profile)

The main outputs are the scalars that vary between members, gauge displacements and Dr2
keys first (at most 8). Uses numpy and matplotlib (Agg) only.
"""
from __future__ import annotations

import argparse
import csv
import datetime as _dt
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dsdem_plotlib as lib  # noqa: E402
import report  # noqa: E402  (house style: CSS, helpers)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

esc = report.esc


def main_outputs(ens: dict, limit: int = 8) -> list[str]:
    varying = [k for k, s in ens["scalars"].items() if "ci95" in s]
    skip = ("final_energies.", "steps", "dt_", "energy_balance_error", "end_time_s", "elements", "nodes", "joints",
            "gauges_from_run_start.")

    def rank(k: str) -> tuple[int, str]:
        # The skip list first: gauges_from_run_start.* repeat the gauges' own keys.
        if any(k.startswith(s) for s in skip):
            return (4, k)
        if k.startswith("mean_max_displacement") or k.endswith(".max_displacement_m"):
            return (0, k)
        # The reservoir's wave, run-up and water force on the curves (a wet ensemble).
        if k == "max_wave_amplitude_m" or k.startswith("max_runup_m.") or \
                (k.startswith("moving_water.force_on_curves.") and ".max_force" in k):
            return (1, k)
        if k.startswith(("river", "intake", "deposit", "duration")) or k.endswith("peak_velocity_mps"):
            return (2, k)
        return (3, k)

    ordered = sorted(varying, key=rank)
    return [k for k in ordered if rank(k)[0] < 4][:limit] or ordered[:limit]


def label(key: str) -> str:
    q, unit = lib.split_unit(key.split(".")[-1])
    head = ".".join(key.split(".")[:-1])
    return f"{head + ': ' if head else ''}{lib.humanize(q)}{' (' + unit + ')' if unit else ''}"


def grid(n: int) -> tuple[int, int]:
    cols = min(n, 2 if n <= 4 else 3)
    return math.ceil(n / cols), cols


def plot_distributions(ens: dict, keys: list[str], path: Path) -> bool:
    if not keys:
        return False
    rows, cols = grid(len(keys))
    fig, axs = plt.subplots(rows, cols, figsize=(5.2 * cols, 3.6 * rows), squeeze=False)
    for ax, k in zip(axs.ravel(), keys):
        s = ens["scalars"][k]
        x = np.array(s["exceedance"]["value"])
        p = np.array(s["exceedance"]["probability"])
        ax.hist(x, bins=max(5, min(30, int(math.sqrt(len(x))) + 1)), color="#9db8d3", density=True)
        ax.set_xlabel(label(k))
        ax.set_ylabel("density")
        ax2 = ax.twinx()
        ax2.step(x, p, where="post", color="#1f5f99")
        ax2.set_ylim(0, 1.02)
        ax2.set_ylabel("P(X ≥ x)")
        for q, ls in (("p5", ":"), ("p50", "--"), ("p95", ":")):
            ax.axvline(s[q], color="k", ls=ls, lw=0.9)
    for ax in axs.ravel()[len(keys):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def plot_events(ens: dict, path: Path) -> bool:
    ev = [(n, e) for n, e in ens["events"].items() if e.get("n")]
    if not ev:
        return False
    fig, ax = plt.subplots(figsize=(8, 0.5 * len(ev) + 1.4))
    y = np.arange(len(ev))
    p = np.array([e["probability"] for _, e in ev])
    lo = np.array([e["wilson95"][0] for _, e in ev])
    hi = np.array([e["wilson95"][1] for _, e in ev])
    ax.barh(y, p, color="#9db8d3")
    ax.errorbar(p, y, xerr=[p - lo, hi - p], fmt="none", ecolor="k", capsize=3)
    ax.set_yticks(y, [n for n, _ in ev], fontsize=9)
    ax.set_xlim(0, 1)
    ax.set_xlabel("probability (95 % Wilson interval)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def read_csv_columns(path: Path) -> dict[str, np.ndarray]:
    with path.open() as f:
        r = csv.reader(f)
        head = next(r)
        rows = [[float(v) if v else np.nan for v in row] for row in r]
    a = np.array(rows) if rows else np.zeros((0, len(head)))
    return {h: a[:, i] for i, h in enumerate(head)}


def plot_envelopes(out: Path, ens: dict, path: Path) -> bool:
    env = ens.get("envelopes", {})
    if not env.get("file") or not (out / env["file"]).exists():
        return False
    c = read_csv_columns(out / env["file"])
    series = env["series"]
    rows, cols = grid(len(series))
    fig, axs = plt.subplots(rows, cols, figsize=(5.2 * cols, 3.3 * rows), squeeze=False)
    t = c["time_s"]
    for ax, s in zip(axs.ravel(), series):
        ax.fill_between(t, c[s + "_p5"], c[s + "_p95"], color="#9db8d3", label="P5–P95")
        ax.plot(t, c[s + "_p50"], color="#1f5f99", label="P50")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label(s))
        ax.grid(alpha=0.3)
    axs.ravel()[0].legend()
    for ax in axs.ravel()[len(series):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def plot_tornado(ens: dict, keys: list[str], path: Path) -> bool:
    sens = ens.get("sensitivity_spearman", {})
    keys = [k for k in keys if sens.get(k)]
    if not keys:
        return False
    rows, cols = grid(len(keys))
    fig, axs = plt.subplots(rows, cols, figsize=(5.2 * cols, 0.45 * max(len(sens[keys[0]]), 2) * rows + 1.6 * rows),
                            squeeze=False)
    for ax, k in zip(axs.ravel(), keys):
        items = sorted(sens[k].items(), key=lambda kv: abs(kv[1]))
        y = np.arange(len(items))
        v = np.array([r for _, r in items])
        ax.barh(y, v, color=["#c0504d" if r < 0 else "#1f5f99" for r in v])
        ax.set_yticks(y, [n for n, _ in items], fontsize=9)
        ax.set_xlim(-1, 1)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_title(label(k), fontsize=10)
        ax.set_xlabel("Spearman rank correlation")
    for ax in axs.ravel()[len(keys):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def plot_convergence(ens: dict, keys: list[str], path: Path) -> bool:
    conv = ens.get("convergence", {})
    n = conv.get("n", [])
    keys = [k for k in keys if k in conv.get("scalars", {})]
    events = [(name, p) for name, p in conv.get("events", {}).items() if len(set(p)) > 1]
    panels = len(keys) + (1 if events else 0)
    if not n or panels == 0:
        return False
    rows, cols = grid(panels)
    fig, axs = plt.subplots(rows, cols, figsize=(5.2 * cols, 3.3 * rows), squeeze=False)
    flat = list(axs.ravel())
    for ax, k in zip(flat, keys):
        c = conv["scalars"][k]
        ax.plot(n, c["mean"], label="mean")
        ax.plot(n, c["p50"], label="P50")
        ax.plot(n, c["p95"], label="P95")
        ax.set_xlabel("members")
        ax.set_ylabel(label(k))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    if events:
        ax = flat[len(keys)]
        for name, p in events:
            ax.plot(n, p, label=name)
        ax.set_ylim(0, 1)
        ax.set_xlabel("members")
        ax.set_ylabel("probability")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    for ax in flat[panels:]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def plot_deposit(out: Path, ens: dict, path: Path) -> bool:
    dep = ens.get("deposit_hazard", {})
    if not dep.get("file") or not (out / dep["file"]).exists():
        return False
    c = read_csv_columns(out / dep["file"])
    fig, ax = plt.subplots(figsize=(9, 3.6))
    for k, v in c.items():
        if k != "x_m":
            ax.plot(c["x_m"], v, label=k.replace("p_thicker_than_", "d > ").replace("_m", " m"))
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("P(debris thicker than d)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def fmt(v) -> str:
    return lib.fmt_num(v) if v is not None else ""


def scalars_table(ens: dict) -> str:
    rows = ['<table><thead><tr><th>output</th><th class="num">n</th><th class="num">mean</th><th class="num">sd</th>'
            '<th class="num">P5</th><th class="num">P10</th><th class="num">P50</th><th class="num">P90</th>'
            '<th class="num">P95</th><th>95 % intervals (mean; P50; P95)</th></tr></thead><tbody>']
    for k, s in ens["scalars"].items():
        ci = s.get("ci95")
        cis = "" if not ci else "; ".join(f"[{fmt(ci[q][0])}, {fmt(ci[q][1])}]" for q in ("mean", "p50", "p95"))
        cells = "".join(f"<td class='num'>{fmt(s.get(q))}</td>" for q in ("p5", "p10", "p50", "p90", "p95"))
        rows.append(f"<tr><td>{esc(k)}</td><td class='num'>{s['n']}</td><td class='num'>{fmt(s['mean'])}</td>"
                    f"<td class='num'>{fmt(s['sd'])}</td>{cells}<td>{esc(cis)}</td></tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def events_table(ens: dict) -> str:
    rows = ['<table><thead><tr><th>event</th><th class="num">members</th><th class="num">count</th>'
            '<th class="num">probability</th><th>95 % Wilson interval</th></tr></thead><tbody>']
    for name, e in ens["events"].items():
        if "error" in e:
            rows.append(f"<tr><td>{esc(name)}</td><td colspan='4' class='note'>{esc(e['error'])}</td></tr>")
            continue
        w = e["wilson95"]
        rows.append(f"<tr><td>{esc(name)}</td><td class='num'>{e['n']}</td><td class='num'>{e['count']}</td>"
                    f"<td class='num'>{fmt(e['probability'])}</td><td>[{fmt(w[0])}, {fmt(w[1])}]</td></tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def varied_table(ens: dict) -> str:
    rows = ["<table><thead><tr><th>name</th><th>keys</th><th>distribution</th></tr></thead><tbody>"]
    for v in ens["varied"]:
        params = ", ".join(f"{k} {json.dumps(v[k])}" for k in v if k not in ("name", "keys", "distribution"))
        keys = ", ".join(v["keys"][:3]) + (f" (+{len(v['keys']) - 3} more)" if len(v["keys"]) > 3 else "")
        rows.append(f"<tr><td>{esc(v['name'])}</td><td><code>{esc(keys)}</code></td>"
                    f"<td>{esc(v['distribution'])}: {esc(params)}</td></tr>")
    rows.append("</tbody></table>")
    return "\n".join(rows)


def build(out: Path, quiet: bool) -> Path:
    ep = out / "ensemble.json"
    if not ep.exists():
        raise lib.InputError(f"{ep}: not found (run `dsdem ensemble` first)")
    ens = json.loads(ep.read_text())
    pd = out / "plots"
    pd.mkdir(exist_ok=True)
    keys = main_outputs(ens)
    figs = []
    for name, caption, fn in (
        ("distributions.png", "Distributions of the main outputs: histogram, exceedance P(X ≥ x), P5/P50/P95",
         lambda p: plot_distributions(ens, keys, p)),
        ("events.png", "Event probabilities with 95 % Wilson intervals", lambda p: plot_events(ens, p)),
        ("envelopes.png", "Gauge and energy envelopes: P5–P95 band and P50 over time",
         lambda p: plot_envelopes(out, ens, p)),
        ("tornado.png", "Sensitivity: Spearman rank correlation of each output with each varied value",
         lambda p: plot_tornado(ens, keys, p)),
        ("convergence.png", "Convergence: estimates against the number of members", lambda p: plot_convergence(ens, keys, p)),
        ("deposit_hazard.png", "Deposit hazard profile: P(debris thicker than d) along the section",
         lambda p: plot_deposit(out, ens, p)),
    ):
        if fn(pd / name):
            figs.append(f"<figure>{report.img_tag(pd / name, caption)}<figcaption>{esc(caption)} "
                        f"(<code>plots/{esc(name)}</code>)</figcaption></figure>")

    title = ens.get("title") or out.name
    cards = [("members", ens["members"]), ("completed", ens["completed_members"]), ("failed", ens["failed_members"]),
             ("not run", ens["missing_members"]),
             ("sampling", f"{ens['sampling']['method'].replace('_', ' ')}, seed {ens['sampling']['seed']}")]
    for k in keys[:3]:
        s = ens["scalars"][k]
        cards.append((f"{label(k)}: P50 [P5, P95]", f"{fmt(s['p50'])} [{fmt(s['p5'])}, {fmt(s['p95'])}]"))
    card_html = '<div class="cards">' + "".join(
        f'<div class="card"><div class="v">{esc(v)}</div><div class="k">{esc(k)}</div></div>' for k, v in cards) + "</div>"
    sec = []
    nav = []

    def section(anchor: str, heading: str, body: str):
        if body:
            nav.append((anchor, heading))
            sec.append(f'<section id="{anchor}"><h2>{esc(heading)}</h2>\n{body}\n</section>')

    section("key", "Key results", card_html)
    section("varied", "Varied values", varied_table(ens) +
            (f"<p>Fixed overrides: <code>{esc(', '.join(ens['fixed']))}</code></p>" if ens.get("fixed") else ""))
    section("events", "Events", events_table(ens))
    section("plots", "Plots", "\n".join(figs))
    section("scalars", "Every output", f"<p class='note'>{esc(ens['statistics_note'])}.</p>" + scalars_table(ens))
    if ens["failures"]:
        section("failures", "Failed members", report.dict_list_table(ens["failures"], first="member"))
    if not ens["deposit_hazard"].get("file"):
        section("deposit", "Deposit hazard", f"<p class='note'>{esc(ens['deposit_hazard'].get('note', ''))}.</p>")
    now = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    page = f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="dsdem ensemble">
<title>{esc(title)} — dsdem ensemble</title>
<style>{report.CSS}</style>
</head>
<body>
<main>
<header>
<h1>{esc(title)}</h1>
<div class="sub">ensemble <code>{esc(ens['ensemble_file'])}</code> &middot; base <code>{esc(ens['base'])}</code>
 &middot; {esc(now)}</div>
<nav>{''.join(f'<a href="#{a}">{esc(h)}</a>' for a, h in nav)}</nav>
</header>
{chr(10).join(sec)}
<footer>dsdem ensemble: members in <code>members/</code>, one row each in <code>members.csv</code>; statistics in
<code>ensemble.json</code>. Values in SI units per metre of thickness unless stated.</footer>
</main>
</body>
</html>
"""
    path = out / "report.html"
    tmp = out / "report.html.tmp"
    tmp.write_text(page, encoding="utf-8")
    tmp.replace(path)
    if not quiet:
        print(f"wrote {path} ({path.stat().st_size / 1024:.0f} KiB) and {len(figs)} plots in {pd}")
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Plots and OUT/report.html of a dsdem ensemble.")
    ap.add_argument("out", help="output folder of `dsdem ensemble`")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    out = Path(a.out)
    if not out.is_dir():
        raise lib.InputError(f"{out}: no such output folder")
    build(out, a.quiet)
    return 0


if __name__ == "__main__":
    lib.run_main(main)
