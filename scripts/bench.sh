#!/usr/bin/env bash
# Runs every benchmark program built under BUILD_DIR (bench/*.cpp -> BUILD_DIR/bench/bench_*)
# with repetitions, keeps their JSON and console output in out/bench/, and prints a summary of
# medians: per-step costs, the thesis Table 2.1 ratios and the performance targets.
#
#   scripts/bench.sh [BUILD_DIR]        (make bench = scripts/bench.sh build)
#
# Environment:
#   BENCH_REPETITIONS       repetitions per benchmark (default 5); medians are reported
#   BENCH_FILTER            regex passed to --benchmark_filter (default: all)
#   BENCH_OUT               output folder (default out/bench)
#   BCASSIM_BENCH_THREADS   threads for TBB and CHOLMOD's OpenMP (default 1: targets are per core)
#   BENCH_SUMMARY_ONLY=1    only print the summary of the JSON already in BENCH_OUT
# bench_liver_step is a driver of whole assimilation runs: its table goes to BENCH_OUT/*.md.
set -euo pipefail

BUILD=${1:-build}
REPS=${BENCH_REPETITIONS:-5}
FILTER=${BENCH_FILTER:-.}
OUT=${BENCH_OUT:-out/bench}
export BCASSIM_BENCH_THREADS=${BCASSIM_BENCH_THREADS:-1}
export OMP_NUM_THREADS=$BCASSIM_BENCH_THREADS
# CHOLMOD 3's supernodal factorisation asks for num_threads(4) (CHOLMOD_OMP_NUM_THREADS, compiled
# in), which OMP_NUM_THREADS does not override; only the thread limit caps it. Without this the
# factorisation runs 4 OpenMP threads on 2 cores and takes 2-4x longer in wall-clock time.
export OMP_THREAD_LIMIT=$BCASSIM_BENCH_THREADS
export OPENBLAS_NUM_THREADS=$BCASSIM_BENCH_THREADS

shopt -s nullglob
exes=()
for f in "$BUILD"/bench/bench_* "$BUILD"/bench_*; do
  [[ -f $f && -x $f ]] && exes+=("$f")
done
if [[ ${#exes[@]} -eq 0 ]]; then
  echo "bench.sh: no benchmark executables under $BUILD/bench (build with -DBCASSIM_BUILD_BENCH=ON)" >&2
  exit 1
fi

mkdir -p "$OUT"
if [[ ${BENCH_SUMMARY_ONLY:-0} != 1 ]]; then
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "threads: $BCASSIM_BENCH_THREADS, repetitions: $REPS"
  lscpu | grep -E '^(Model name|CPU\(s\)|Thread|Core|L2|L3)' || true
} > "$OUT/machine.txt"
cat "$OUT/machine.txt"

for exe in "${exes[@]}"; do
  name=$(basename "$exe")
  if [[ $name == bench_liver_step ]]; then  # a driver of whole runs, not Google Benchmark
    echo
    echo "=== $name (phantom liver, 100 steps per configuration) ==="
    "$exe" phantom 100 "$OUT" | tee "$OUT/$name.md"
    continue
  fi
  echo
  echo "=== $name (repetitions $REPS, filter '$FILTER') ==="
  "$exe" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
    --benchmark_filter="$FILTER" \
    --benchmark_out="$OUT/$name.json" --benchmark_out_format=json | tee "$OUT/$name.txt"
done
fi

python3 - "$OUT" <<'EOF' | tee "$OUT/summary.md"
import glob, json, os, re, sys

out = sys.argv[1]
rows = {}  # name -> (median wall ms, cv %, median CPU ms, counters of the median aggregate)
to_ms = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
skip = {"name", "run_name", "run_type", "repetitions", "repetition_index", "threads",
        "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name", "family_index",
        "per_family_instance_index", "aggregate_unit"}
for path in sorted(glob.glob(os.path.join(out, "*.json"))):
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError):  # empty when the filter matched nothing in that program
        continue
    runs = data.get("benchmarks", [])
    med = {r["run_name"]: r for r in runs if r.get("aggregate_name") == "median"}
    cv = {r["run_name"]: r for r in runs if r.get("aggregate_name") == "cv"}
    single = {r["run_name"]: r for r in runs if r.get("run_type") == "iteration"}
    for run_name, r in (med or single).items():
        name = re.sub(r"/(iterations:\d+|real_time)", "", run_name)
        ms = r["real_time"] * to_ms[r.get("time_unit", "ns")]
        c = cv.get(run_name)
        cpu = r["cpu_time"] * to_ms[r.get("time_unit", "ns")]
        rows[name] = (ms, 100 * c["real_time"] if c else None, cpu,
                      {k: v for k, v in r.items() if k not in skip and isinstance(v, (int, float))})

def fmt(x):
    return "-" if x is None else (f"{x:.3g}" if abs(x) < 100 else f"{x:.0f}")

print("\n## Medians (wall-clock ms per iteration)\n")
print("| benchmark | median ms | cv % | median CPU ms | counters (medians) |")
print("|---|---:|---:|---:|---|")
for name, (ms, cvp, cpu, counters) in rows.items():
    cs = ", ".join(f"{k} {fmt(v)}" for k, v in counters.items())
    print(f"| {name} | {ms:.3f} | {fmt(cvp)} | {cpu:.3f} | {cs} |")

thesis = {"corotational": 402.73, "stvk": 425.02, "neohookean": 451.64, "mooneyrivlin": 503.68}
mats = ["corotational", "stvk", "neohookean", "mooneyrivlin", "linear"]
for kind in ["step_cholmod", "step_factorized_pcg", "assembly"]:
    got = {m: rows[f"beam26000/{kind}/{m}"][0] for m in mats if f"beam26000/{kind}/{m}" in rows}
    if "corotational" not in got:
        continue
    print(f"\n## Thesis Table 2.1 analogue: beam26000/{kind}\n")
    cpu = {m: rows[f"beam26000/{kind}/{m}"][2] for m in got}
    print("| material | wall ms | wall ratio | CPU ms | CPU ratio | thesis ms | thesis ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for m, ms in got.items():
        t = thesis.get(m)
        tr = f"{t / thesis['corotational']:.3f}" if t else "-"
        print(f"| {m} | {ms:.2f} | {ms / got['corotational']:.3f} | {cpu[m]:.2f} | "
              f"{cpu[m] / cpu['corotational']:.3f} | {t if t else '-'} | {tr} |")

targets = [("beam8600/assembly/stvk", 5.0, "StVK force+tangent assembly, ~8,600 tets, one core"),
           ("cylinder2200/step_factorized_pcg", 10.0, "reuse-PCG implicit-Euler step, ~2,200 nodes, one core"),
           ("cylinder2200/step_factorized_pcg_background_every2", 10.0,
            "the same, factor refreshed every 2 steps on the second core")]
print("\n## Targets\n")
print("| target | benchmark | limit ms | median wall ms | median CPU ms | met (wall / CPU) |")
print("|---|---|---:|---:|---:|---|")
for name, limit, what in targets:
    if name not in rows:
        continue
    ms, cpu = rows[name][0], rows[name][2]
    verdict = " / ".join("yes" if v <= limit else f"NO ({v / limit:.2f}x)" for v in (ms, cpu))
    print(f"| {what} | {name} | {limit:g} | {ms:.3f} | {cpu:.3f} | {verdict} |")
EOF
echo
echo "bench.sh: results in $OUT/ (*.json, *.txt, summary.md, machine.txt)"
