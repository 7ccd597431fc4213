#!/bin/sh
# The three cases again with the settle a hundredth of a second longer each time: the same
# physics, a slightly different water at impact, so the spread of the ratios to Heller &
# Hager's a_M is the granular flow's own scatter (README.md). Then scatter.py: scatter.md.
# Usage: examples/impulse_wave/scatter.sh [OUT_ROOT]   (default: out/impulse_wave_scatter)
# Environment: DSDEM, SETTLES (default "0.50 0.51 0.52 0.53 0.54").
set -e
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-out/impulse_wave_scatter}
for s in ${SETTLES:-0.50 0.51 0.52 0.53 0.54}; do
  SETTLE=$s RESULTS="$OUT/settle_$s" sh "$HERE/run.sh" "$OUT/settle_$s"
done
/usr/bin/python3 "$HERE/scatter.py" "$OUT"
