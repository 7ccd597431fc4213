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
# The water: the pool of the scenario (reservoir.level 837 m over x 600.8-866 m) filled below its
# level, settled for 20 s before the run. Surface gauges over the near bank (650 m), the intake's
# side of the river (700 m), mid-river (765 m) and the far bank (830 m); run-up on the far (left)
# bank, the bedrock surface of dr2.geo from the river bed's left edge up; the water's force on a
# 20 m stretch of the ground around the intake (715, 750.8).
WET=(--set reservoir.sph.spacing="$DP" --set reservoir.sph.expected_speed=15 --set reservoir.sph.settle=20
     --set "reservoir.sph.gauges=[{name: g650, x: 650}, {name: g700, x: 700}, {name: g765, x: 765}, {name: g830, x: 830}]"
     --set "reservoir.sph.runup=[{name: left_bank, polyline: [[810, 745], [880, 860], [980, 1040]]}]"
     --set "reservoir.sph.pressure=[{name: intake, polyline: [[708, 759], [720, 745]]}]")
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
