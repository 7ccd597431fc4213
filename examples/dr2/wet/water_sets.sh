# The Dr2 pool as moving water (docs/dr2.md §10), shared by scripts/demo.sh, scripts/bench.sh and
# examples/dr2/wet/run.sh. Sourced; `dr2_water_sets SPACING [BANK]` sets the array DR2_WATER to
# the --set options: the pool of the scenario (reservoir.level 837 m over x 600.8-866 m) filled
# below its level with particles SPACING m apart, settled for 20 s before the run; surface gauges
# over the near bank (650 m), the intake's side of the river (700 m), mid-river (765 m) and the
# far bank (830 m); run-up on the far (left) bank, the bedrock surface of dr2.geo from the river
# bed's left edge up, named BANK (default far_bank); the water's force on a 20 m stretch of the
# ground around the intake (715, 750.8).
dr2_water_sets() {
  local dp=$1 bank=${2:-far_bank}
  DR2_WATER=(--set reservoir.sph.spacing="$dp" --set reservoir.sph.expected_speed=15 --set reservoir.sph.settle=20
             --set "reservoir.sph.gauges=[{name: g650, x: 650}, {name: g700, x: 700}, {name: g765, x: 765}, {name: g830, x: 830}]"
             --set "reservoir.sph.runup=[{name: $bank, polyline: [[810, 745], [880, 860], [980, 1040]]}]"
             --set "reservoir.sph.pressure=[{name: intake, polyline: [[708, 759], [720, 745]]}]")
}
