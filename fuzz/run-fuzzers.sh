#!/usr/bin/env bash
# `make fuzz`: builds the libFuzzer targets (clang-14, AddressSanitizer + UBSan, in the sanitized
# build build-sanitize/ that `make sanitize` shares) and runs each for FUZZ_SECONDS seconds (default 60), JOBS targets at a time, from its seed corpus
# fuzz/corpus/<target>/ and what earlier runs found (build-sanitize/corpus/<target>/). Any finding
# (crash, undefined behaviour, leak, a run over 10 s, an allocation over 1 GiB) fails the run and
# leaves its input in build-sanitize/findings/<target>/: fix it and add the input to tests/data/bad/.
# Prints the executions per target (docs/robustness.md records them).
set -uo pipefail
cd "$(dirname "$0")/.."

SECONDS_EACH=${FUZZ_SECONDS:-60}
JOBS=${JOBS:-2}
[ "$JOBS" -ge 1 ] 2>/dev/null || JOBS=1  # 0 or not a number: one at a time
TARGETS=${FUZZ_TARGETS:-gmsh medit legacy_vtk vtk_xml obj stl ply csv_table csv_tracks detections_csv eseg npy index_list rigid_transform point_cloud scene_yaml checkpoint igtl_message spring_priors}
# FUZZ_RUNS=N: stop each target after N executions instead (FUZZ_SECONDS is then only a cap).
RUNS=${FUZZ_RUNS:--1}

BUILD=$(bash scripts/configure-sanitized.sh) || exit 1
build_targets=()
for t in $TARGETS; do build_targets+=("fuzz_$t"); done
cmake --build "$BUILD" -j"$JOBS" --target "${build_targets[@]}" > "$BUILD/fuzz-build.log" 2>&1 ||
  { tail -40 "$BUILD/fuzz-build.log"; exit 1; }

# A small quarantine keeps memory (and page faults) low: 2 to 3 times the executions.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:quarantine_size_mb=16:malloc_context_size=10}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One target per job, JOBS of them at a time (each is single-threaded), the rows printed in order.
run_one() {
  local t=$1
  mkdir -p "$BUILD/corpus/$t" "$BUILD/findings/$t"
  "$BUILD/fuzz/fuzz_$t" -max_total_time="$SECONDS_EACH" -runs="$RUNS" -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=1024 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$BUILD/findings/$t/" "$BUILD/corpus/$t" "fuzz/corpus/$t" > "$BUILD/findings/$t.log" 2>&1
  echo $? > "$BUILD/findings/$t.status"
}
targets=($TARGETS)
for ((i = 0; i < ${#targets[@]}; i += JOBS)); do
  for t in "${targets[@]:i:JOBS}"; do run_one "$t" & done
  wait
done

failed=()
printf '%-14s %14s %8s  %s\n' target executions seconds result
for t in "${targets[@]}"; do
  log="$BUILD/findings/$t.log"
  status=$(cat "$BUILD/findings/$t.status" 2>/dev/null || echo 1)
  runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  if [ "$status" -eq 0 ]; then
    result=ok
  else
    result="FINDING (exit $status): see $log and $BUILD/findings/$t/"
    failed+=("$t")
  fi
  seconds=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | grep -o '[0-9]* second' | grep -o '[0-9]*' || echo "$SECONDS_EACH")
  printf '%-14s %14s %8s  %s\n' "$t" "$runs" "$seconds" "$result"
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
