#!/usr/bin/env bash
# The artificial wave's spectral fit over many seeds: runs `dsdem wave generate` for
# seeds FIRST..LAST (default 1..100) with the Dr2 target (the defaults: hydraulic beta
# spectrum, 0.05 g, Tg 0.35 s, dt 0.02 s, 10 s) and prints, per seed, the lowest and
# highest Sa/target - 1 over 0.1-6 s over the record alone and with the oscillator's
# free vibration after it, then the worst of all seeds. Extra arguments go to
# `dsdem wave generate`.
#   scripts/wave_seeds.sh [FIRST [LAST [generate options...]]]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
dsdem=${DSDEM:-$here/build/dsdem}
first=${1:-1}
last=${2:-100}
shift $(( $# < 2 ? $# : 2 ))
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf "%5s %26s %26s %9s %8s\n" seed "record: low / high" "free vib.: low / high" "attempts" "time_s"
for seed in $(seq "$first" "$last"); do
  start=$(date +%s.%N)
  out=$("$dsdem" wave generate --seed "$seed" --no-plot -o "$tmp/w.csv" "$@")
  end=$(date +%s.%N)
  echo "$out" | awk -v seed="$seed" -v secs="$(echo "$end - $start" | bc)" '
    /corrections/ { match($0, /[0-9]+ phase set/); att = substr($0, RSTART, RLENGTH - 10) }
    /record alone/ { rl = $(NF-8); rlt = $(NF-6); rh = $(NF-3); rht = $(NF-1) }
    /free vibration/ { fl = $(NF-8); flt = $(NF-6); fh = $(NF-3); fht = $(NF-1) }
    END { printf "%5d %12s@%-5s %7s@%-5s %12s@%-5s %7s@%-5s %5s %8.2f\n", seed, rl, rlt, rh, rht, fl, flt, fh, fht, att, secs }'
done | tee "$tmp/table"
awk '
  function v(s) { sub(/@.*/, "", s); sub(/%/, "", s); return s + 0 }
  function worse(s, w) { return (v(s) < 0 ? -v(s) : v(s)) > w }
  { for (k = 2; k <= 5; ++k) { x = v($k); a = x < 0 ? -x : x; if (k <= 3 && a > wr) { wr = a; wrs = $1; wrw = $k } if (k >= 4 && a > wf) { wf = a; wfs = $1; wfw = $k } }
    if (v($2) < -10 || v($3) > 10) nr++; if (v($4) < -10 || v($5) > 10) nf++; t += $7; n++ }
  END { printf "worst over the record: %s (seed %d); with free vibration: %s (seed %d)\n", wrw, wrs, wfw, wfs
        printf "seeds outside 10%%: %d over the record, %d with free vibration, of %d; mean %.2f s per seed\n", nr, nf, n, t / n }' "$tmp/table"
