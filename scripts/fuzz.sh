#!/usr/bin/env bash
# Builds the libFuzzer targets (clang + ASan + UBSan) and runs each on its corpus.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 30 s, all four targets)
# Environment: FUZZ_BUILD (build dir, default build-fuzz), FUZZ_JOBS (default 2),
# FUZZ_KEEP_CORPUS=1 to merge new inputs back into fuzz/corpus/<target>/.
# Exit code non-zero when a target crashes, hangs (> 10 s on one input) or leaks memory;
# the reproducer is left as build-fuzz/artifacts/<target>/crash-*.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-30}
shift || true
# `ci`: a reproducible smoke, seed 1 and a fixed number of runs per target (about 30 s
# each here): CI must not pass or fail by the luck of a time budget.
CI_MODE=0
NO_ASLR=()
if [ "$SECONDS_PER_TARGET" = "ci" ]; then
  CI_MODE=1; SECONDS_PER_TARGET=30
  # Without address randomisation: the coverage that guides libFuzzer's choice of inputs
  # depends on heap addresses (yaml-cpp orders its nodes by pointer), so with ASLR the
  # same seed tested different inputs in every run.
  if setarch "$(uname -m)" -R true 2> /dev/null; then NO_ASLR=(setarch "$(uname -m)" -R); fi
fi
ci_runs() {
  case "$1" in
    fuzz_scenario) echo 20000 ;;
    fuzz_accel_at2) echo 100000 ;;
    fuzz_accel_csv) echo 20000 ;;
    fuzz_msh) echo 100000 ;;
    *) echo 5000 ;;
  esac
}
TARGETS=("$@")
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=(fuzz_scenario fuzz_msh fuzz_accel_csv fuzz_accel_at2)
BUILD=${FUZZ_BUILD:-build-fuzz}
JOBS=${FUZZ_JOBS:-2}
CXX_FUZZ=${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}
CC_FUZZ=${CC_FUZZ:-$(command -v clang-14 || command -v clang)}

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  CC="$CC_FUZZ" CXX="$CXX_FUZZ" cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DDSDEM_BUILD_FUZZ=ON -DDSDEM_BUILD_TESTS=OFF -DDSDEM_BUILD_BENCH=OFF > /dev/null
fi
cmake --build "$BUILD" --target dsdem_fuzz_all -j "$JOBS"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
for t in "${TARGETS[@]}"; do
  art="$BUILD/artifacts/$t"
  work="$BUILD/corpus-work/$t"
  # The smoke starts from the seed corpus alone: inputs a previous run kept in the scratch
  # corpus would make its result depend on that run.
  if [ "$CI_MODE" = 1 ]; then rm -rf "$work"; fi
  mkdir -p "$art" "$work"
  echo "fuzz: $t for ${SECONDS_PER_TARGET} s"
  # New inputs go to a scratch corpus; the repository's seed corpus is read only.
  # -reload=0: libFuzzer rereads its corpus folders once a second by default, so which
  # inputs it mutated next depended on the machine's speed.
  if [ "$CI_MODE" = 1 ]; then LIMIT=(-seed=1 -reload=0 -runs="$(ci_runs "$t")"); else LIMIT=(-max_total_time="$SECONDS_PER_TARGET"); fi
  if ! ${NO_ASLR[@]+"${NO_ASLR[@]}"} "$BUILD/fuzz/$t" "${LIMIT[@]}" -timeout=10 -rss_limit_mb=2048 \
        -max_len=8192 -print_final_stats=1 -artifact_prefix="$art/" "$work" "fuzz/corpus/$t" \
        > "$BUILD/$t.log" 2>&1; then
    echo "fuzz: $t FAILED; see $BUILD/$t.log and $art/"
    tail -40 "$BUILD/$t.log"
    status=1
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|cov:" "$BUILD/$t.log" | tail -3 || true
  if [ "${FUZZ_KEEP_CORPUS:-0}" = 1 ]; then
    "$BUILD/fuzz/$t" -merge=1 "fuzz/corpus/$t" "$work" > /dev/null 2>&1 || true
  fi
done
exit $status
