#!/usr/bin/env bash
# The analytic ensemble of tests/ensemble (block on a 30-degree incline, friction uniform in
# [0.1, 0.5], Monte Carlo, seed 4) at N = 25, 100 and 400 members: the widths of the 95 %
# intervals of the mean, the P50 and P(x > d) against N, which should fall like 1/sqrt(N).
# The unit test runs 25 and 100; this adds 400 (about 400 x 0.2 s of CPU).
#   bench/ensemble_convergence.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
OUT=${2:-/tmp/dsdem_ensemble_convergence}
mkdir -p "$OUT"
BASE=$(pwd)/tests/data/ensemble/incline.yaml
D=0.144264   # x(mu = 0.2) at t = 0.3 s: P(x > D) = 0.25
for N in 25 100 400; do
  cat > "$OUT/ens.yaml" <<YAML
base: $BASE
members: $N
sampling: {method: monte_carlo, seed: 4}
vary:
  - {key: contact.friction, name: friction, distribution: uniform, lower: 0.1, upper: 0.5}
events: ["gauges.block.final_displacement_m.0 > $D"]
YAML
  # Monte Carlo draws member by member: the first N members of a larger ensemble are the
  # smaller one, so each step runs only the new members.
  "$BUILD/dsdem" ensemble "$OUT/ens.yaml" -o "$OUT/out" -q --no-plots
  cp "$OUT/out/ensemble.json" "$OUT/ensemble_$N.json"
done
/usr/bin/python3 - "$OUT" "$D" <<'PY'
import json, math, sys
out, d = sys.argv[1], float(sys.argv[2])
key = "gauges.block.final_displacement_m.0"
gs, gc = 4.905, 8.495709211
prev = None
print(f"{'N':>5} {'P50':>9} {'P50 95% interval':>22} {'exact':>8} {'P(x>d)':>7} {'Wilson 95%':>16} {'exact':>6}"
      f" {'w_mean':>8} {'w_P50':>8} {'w_P':>7}  ratios to the previous N (1/sqrt: 2.0)")
for n in (25, 100, 400):
    e = json.load(open(f"{out}/ensemble_{n}.json"))
    t = e["scalars"]["end_time_s"]["p50"]
    s, ev = e["scalars"][key], e["events"][f"{key} > {d:f}"]
    exact50 = 0.5 * (gs - 0.3 * gc) * t * t
    exactp = ((gs - 2 * d / t / t) / gc - 0.1) / 0.4
    ci, w = s["ci95"], ev["wilson95"]
    widths = (ci["mean"][1] - ci["mean"][0], ci["p50"][1] - ci["p50"][0], w[1] - w[0])
    ratios = "" if prev is None else "  " + " ".join(f"{a / b:.2f}" for a, b in zip(prev, widths))
    inside = ci["p50"][0] <= exact50 <= ci["p50"][1] and w[0] <= exactp <= w[1]
    print(f"{n:>5} {s['p50']:9.4f} [{ci['p50'][0]:.4f}, {ci['p50'][1]:.4f}] {exact50:8.4f} {ev['probability']:7.3f}"
          f" [{w[0]:.3f}, {w[1]:.3f}] {exactp:6.3f} {widths[0]:8.4f} {widths[1]:8.4f} {widths[2]:7.4f}{ratios}"
          f"{'' if inside else '  EXACT VALUE OUTSIDE ITS INTERVAL'}")
    prev = widths
PY
