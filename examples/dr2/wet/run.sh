#!/bin/bash
# Dr2 with the reservoir as moving water (docs/dr2.md §10): each mode at the 12 m mesh, dry and
# with the pool (837 m) as SPH water 2 m apart, one thread each, then the table (table.py).
# Usage: examples/dr2/wet/run.sh [OUT_ROOT] [MODE ...]   (default out/dr2_wet, all three modes)
# Environment: DSDEM (default build/dsdem), ELEMENT_SIZE (12), SPACING (2), KINDS ("dry wet").
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../../.." && pwd)
OUT=${1:-out/dr2_wet}
shift || true
MODES=("$@")
[ ${#MODES[@]} -gt 0 ] || MODES=(shear_sliding local_collapse slip_j1)
DSDEM=${DSDEM:-$ROOT/build/dsdem}
H=${ELEMENT_SIZE:-12}
DP=${SPACING:-2}
# The water (water_sets.sh): the pool settled for 20 s, four surface gauges, the far bank's
# run-up (left_bank, as table.py reads it), the water's force around the intake.
source "$HERE/water_sets.sh"
dr2_water_sets "$DP" left_bank
WET=("${DR2_WATER[@]}")
mkdir -p "$OUT"
for mode in "${MODES[@]}"; do
  for kind in ${KINDS:-dry wet}; do
    dir="$OUT/${mode}_$kind"
    extra=()
    [ "$kind" = wet ] && extra=("${WET[@]}")
    echo "$mode, $kind: $dir"
    start=$EPOCHREALTIME
    "$DSDEM" run "$ROOT/examples/dr2/$mode.yaml" -o "$dir" --threads 1 --quiet --no-plots \
      --set mesh.element_size="$H" "${extra[@]}"
    end=$EPOCHREALTIME
    /usr/bin/python3 -c "print(round($end - $start, 1))" > "$dir/wall_seconds"
    /usr/bin/python3 "$ROOT/scripts/dr2_postprocess.py" "$dir" --mode "$mode" --quiet
  done
done
/usr/bin/python3 "$HERE/table.py" "$OUT" "${MODES[@]}"
