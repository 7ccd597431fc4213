#!/usr/bin/env bash
# The main job: runs the flagship example end to end and says where the results are.
set -euo pipefail
BUILD=${1:-build}
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
DSDEM="$ROOT/$BUILD/dsdem"
SETS=()
if [ -f "$ROOT/examples/dr2/shear_sliding.yaml" ]; then
  SCENARIO="$ROOT/examples/dr2/shear_sliding.yaml"
  OUT="$ROOT/results/dr2_shear_sliding"
  # The demo runs the 12 m mesh (about 1.2k triangles, minutes); the default 4 m mesh
  # (about 8.6k triangles) is `dsdem run examples/dr2/shear_sliding.yaml -o OUT`.
  SETS=(--set mesh.element_size=${DEMO_ELEMENT_SIZE:-12})
else
  SCENARIO="$ROOT/examples/elastic_slope/scenario.yaml"
  OUT="$ROOT/results/elastic_slope"
fi
# One job: the run, the Dr2 post-processing and movie, the report, the time taken.
#   run_job OUT [--set ...]
run_job() {
  local out=$1
  shift
  local start end
  start=$(date +%s)
  "$DSDEM" run "$SCENARIO" -o "$out" "$@"
  if [ -f "$ROOT/scripts/dr2_postprocess.py" ] && [[ "$SCENARIO" == *dr2* ]]; then
    /usr/bin/python3 "$ROOT/scripts/dr2_postprocess.py" "$out" --movie --dsdem "$DSDEM" || echo "warning: Dr2 post-processing failed"
  fi
  "$DSDEM" report "$out" > /dev/null || echo "warning: the HTML report could not be made"
  end=$(date +%s)
  echo
  echo "Done in $((end - start)) s. Results in $out:"
}
echo "dsdem demo: $SCENARIO"
"$DSDEM" check "$SCENARIO" "${SETS[@]}"
run_job "$OUT" "${SETS[@]}"
echo "  summary.json     key numbers"
echo "  history.csv      gauges and energies over time"
echo "  fields.pvd       open in ParaView (deformed mesh, stress, velocity)"
echo "  plots/           PNG plots of the histories"
echo "  report.html      everything on one page"
if [ -f "$OUT/dr2.json" ]; then
  echo "  dr2.json         Dr2 numbers (also merged into summary.json); docs/dr2.md compares them with the paper"
  echo "  dr2_plots/       gauges.png, snapshots.png, deposit.png (final deposit over the original ground), energy.png"
  echo "  render/material.mp4  animation"
fi

# Beyond the paper: the same slide into the reservoir as moving water (docs/dr2.md §10), the
# water 4 m apart (a third of the mesh; the far bank's wave and run-up of the finer spacings),
# about twice the dry run's time. DEMO_WATER=0 skips it.
if [ "${DEMO_WATER:-1}" != 0 ] && [[ "$SCENARIO" == *dr2/shear_sliding* ]]; then
  WET_OUT="$ROOT/results/dr2_shear_sliding_reservoir"
  source "$ROOT/examples/dr2/wet/water_sets.sh"
  dr2_water_sets 4 far_bank
  WET=("${DR2_WATER[@]}")
  echo
  echo "dsdem demo, with the reservoir: $SCENARIO"
  run_job "$WET_OUT" "${SETS[@]}" "${WET[@]}"
  echo "  (as above, and)"
  echo "  water.pvd        the water's particles (velocity, pressure) for ParaView"
  echo "  summary.json     max_wave_amplitude_m, max_runup_m (far bank), heller_hager, moving_water (intake force)"
  echo "  render/material.mp4  rock and water together"
fi
