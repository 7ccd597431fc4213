#!/bin/sh
# Runs the three cases of the granular slide into still water (impulse_wave.yaml with --set
# overrides of the still water depth, the particle spacing and the expected entry speed),
# one thread each, then compare.py: results.md and impulse_wave.png beside this script.
# Usage: examples/impulse_wave/run.sh [OUT_ROOT]   (default: out/impulse_wave)
# Environment: DSDEM (default build/dsdem), SETTLE (s, reservoir.sph.settle; default the
# scenario's), RESULTS (where results.md and the plot go; default beside this script).
set -e
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
OUT=${1:-out/impulse_wave}
DSDEM=${DSDEM:-$ROOT/build/dsdem}
RESULTS=${RESULTS:-$HERE}
SETTLE_SET=""
[ -n "${SETTLE:-}" ] && SETTLE_SET="--set reservoir.sph.settle=$SETTLE"
mkdir -p "$OUT"
# case  depth h (m)  spacing dp (m)  expected entry speed (m/s)
# dp: the slide (s = 0.15 m thick) at least 7 particles across, the water 15 or more deep, and
# h a whole number of spacings (else the bottom row is missing: the run warns).
while read -r name level spacing speed; do
  echo "case $name: h = $level m, dp = $spacing m"
  start=$(date +%s)
  OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U" -o "$OUT/$name.time" "$DSDEM" run "$HERE/impulse_wave.yaml" -o "$OUT/$name" --threads 1 --quiet --no-plots \
    --set reservoir.level="$level" --set reservoir.sph.spacing="$spacing" \
    --set reservoir.sph.expected_speed="$speed" $SETTLE_SET
  echo $(( $(date +%s) - start )) > "$OUT/$name/wall_seconds"
  cut -d' ' -f2 "$OUT/$name.time" > "$OUT/$name/cpu_seconds"
done <<CASES
A 0.25 0.0166667 3.0
B 0.40 0.02 3.0
C 0.55 0.022 3.0
CASES
/usr/bin/python3 "$HERE/compare.py" "$OUT/A" "$OUT/B" "$OUT/C" -o "$RESULTS"
