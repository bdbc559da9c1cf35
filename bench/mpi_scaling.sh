#!/usr/bin/env bash
# The MPI executor's ranks x threads scaling and the measurements of its cost model
# (docs/benchmarks.md §8): the full-state UKF of examples/cyl-E-same (2,792 sigma points) and the
# liver ROUKF of `make demo`, each for a few steps at 1x1, 1x2, 2x1 and 2x2 (ranks x threads;
# more than 2 cores' worth is oversubscribed), then bench_mpi_transfer's latency and bandwidth
# and the model's predictions for 8, 64 and 512 ranks.
# Usage: bench/mpi_scaling.sh [BUILD=build] [OUT=out/bench/mpi]
#   UKF_STEPS (default 6) and LIVER_STEPS (default 60): steps run (trimmed copies of the scenes);
#   LIVER (default LiTS-3 from $BCASSIM_DATA, else the built-in phantom); SUMMARY_ONLY=1 reprints
#   the tables from the runs in OUT.
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(cd "${1:-build}" && pwd)
OUT=${2:-out/bench/mpi}
UKF_STEPS=${UKF_STEPS:-6}
LIVER_STEPS=${LIVER_STEPS:-60}
export BCASSIM_DATA=${BCASSIM_DATA:-$HERE/../shared/data}
LIVER=${LIVER:-LiTS-3}
[ -f "$BCASSIM_DATA/livers/$LIVER.obj" ] || LIVER=phantom
B=$BUILD/bcassim
# No --oversubscribe (2 ranks fit 2 cores): with it OpenMPI yields the core while waiting, and
# on a busy machine every message then waits for the scheduler (4 ms measured).
MPIRUN=(mpirun --bind-to none)
[ "$(id -u)" = 0 ] && MPIRUN+=(--allow-run-as-root)
mkdir -p "$OUT" && OUT=$(cd "$OUT" && pwd)

# run NAME SCENE RANKS THREADS: one assimilation into $OUT/runs/NAME-RxT.
run() {
  local dir=$OUT/runs/$1-$3x$4
  rm -rf "$dir" && mkdir -p "$OUT/runs"
  if [ "$3" = 1 ]; then
    "$B" assimilate "$2" --out "$dir" --threads "$4" -q --no-plots > "$dir.txt"
  else
    "${MPIRUN[@]}" -np "$3" "$B" assimilate "$2" --out "$dir" --threads "$4" --mpi -q --no-plots \
      > "$dir.txt"
  fi
}

if [ -z "${SUMMARY_ONLY:-}" ]; then
# The full-state UKF: copies of the example scenes with the steps trimmed.
mkdir -p "$OUT/examples"
cp -r "$HERE/examples/cyl-E-same" "$HERE/examples/cyl-common" "$OUT/examples/"
sed -i -E "s/^time: \{dt: 0.01, steps: [0-9]+\}/time: {dt: 0.01, steps: $UKF_STEPS}/" \
  "$OUT/examples/cyl-E-same/truth.yaml" "$OUT/examples/cyl-E-same/estimate-ukf.yaml"
"$B" simulate "$OUT/examples/cyl-E-same/truth.yaml" --out "$OUT/out/cyl-E-same/truth" -q > /dev/null

# The liver ROUKF of `make demo` (scripts/demo.sh: 5,000-node truth), trimmed.
"$B" liver prepare "$LIVER" --out "$OUT/liver" --fine-nodes 5000 --steps "$LIVER_STEPS" \
  --observed-steps "$LIVER_STEPS" > /dev/null
"$B" simulate "$OUT/liver/truth.yaml" --out "$OUT/liver/truth" -q > /dev/null

for config in "1 1" "1 2" "2 1" "2 2"; do
  # shellcheck disable=SC2086
  run ukf "$OUT/examples/cyl-E-same/estimate-ukf.yaml" $config
  # shellcheck disable=SC2086
  run liver "$OUT/liver/estimate.yaml" $config
done
"${MPIRUN[@]}" -np 2 "$BUILD/bench/bench_mpi_transfer" > "$OUT/transfer.txt"
# The UKF's dense algebra alone and shared by 2 ranks, one BLAS thread per rank.
OPENBLAS_NUM_THREADS=1 "$BUILD/bench/bench_dense_algebra" > "$OUT/dense.txt"
OPENBLAS_NUM_THREADS=1 "${MPIRUN[@]}" -x OPENBLAS_NUM_THREADS -np 2 \
  "$BUILD/bench/bench_dense_algebra" >> "$OUT/dense.txt"
fi

python3 - "$OUT" <<'PY'
import csv, math, re, statistics, sys
out = sys.argv[1]

def steps(name, config, pick=statistics.median):
    rows = list(csv.DictReader(open(f"{out}/runs/{name}-{config}/timing.csv")))[1:]  # step 1: set-up
    med = lambda k: pick(float(r[k]) for r in rows)
    return med("total_ms"), med("forecast_ms"), med("correction_ms")

def steps_of(name, config):
    return len(list(csv.DictReader(open(f"{out}/runs/{name}-{config}/timing.csv"))))

def final(name, config):
    rows = list(csv.DictReader(open(f"{out}/runs/{name}-{config}/estimates.csv")))
    last = rows[-1]["step"]
    return [float(r["mean"]) for r in rows if r["step"] == last]

def mpi_line(name, config):
    text = open(f"{out}/runs/{name}-{config}.txt").read()
    return " ".join(re.findall(r"^MPI: .*$", text, re.M))

transfer = open(f"{out}/transfer.txt").read()
print(transfer)
latency = float(re.search(r"latency \(8 B\): ([0-9.e+-]+) us", transfer).group(1)) * 1e-6
bandwidth = float(re.search(r"bandwidth \(\d+ B\): ([0-9.e+-]+) GB/s", transfer).group(1)) * 1e9

configs = ["1x1", "1x2", "2x1", "2x2"]
for name in ["ukf", "liver"]:
    base_total = steps(name, "1x1")[0]
    base_final = final(name, "1x1")
    base_best = steps(name, "1x1", min)[0]
    print(f"\n{name}: ranks x threads | step median ms | forecast | correction | speed-up | "
          "fastest step ms | its speed-up | final estimates, max relative difference to 1x1 | MPI")
    for c in configs:
        total, forecast, correction = steps(name, c)
        best = steps(name, c, min)[0]
        diff = max(abs(a - b) / max(abs(a), abs(b)) for a, b in zip(final(name, c), base_final))
        print(f"| {c} | {total:.1f} | {forecast:.1f} | {correction:.1f} | "
              f"{base_total / total:.2f} | {best:.1f} | {base_best / best:.2f} | {diff:.1e} | "
              f"{mpi_line(name, c)}")

# The cost model of one step on R ranks of one thread each:
#   T(R) = A + ceil(S/R) t + C(R),  C(R) = 3 (min(R,S)-1) L + [8 n + 8 (n + m)] (S - ceil(S/R)) / W
#          + (R-1) (L + 8 n / W)
# A: rank 0's filter algebra (step minus forecasts), t: one sigma point's forecast, S sigma
# points of n entries with m observables; L, W: latency and bandwidth of rank 0's link, every
# transfer serialised through it (blocks out, forecasts back, the mean to every rank).
def model(name, S, n, m):
    total, forecast, _ = steps(name, "1x1")
    t = forecast / 1e3 / S
    A = (total - forecast) / 1e3
    print(f"\n{name} model: S {S}, n {n}, m {m}, t {1e3 * t:.3f} ms per sigma point, "
          f"A {1e3 * A:.1f} ms rank 0's algebra")
    for label, L, W in [("this machine (shared memory)", latency, bandwidth),
                        ("cluster (L 2 us, W 12 GB/s: 100 Gb/s InfiniBand)", 2e-6, 12e9),
                        ("cluster (L 20 us, W 1.25 GB/s: 10 Gb/s Ethernet)", 20e-6, 1.25e9)]:
        cells = []
        for R in [1, 2, 8, 64, 512]:
            per = math.ceil(S / R)
            busy = min(R, S)  # ranks with columns; the others only get the mean
            C = 0.0 if R == 1 else (3 * (busy - 1) * L + (8 * n + 8 * (n + m)) * (S - per) / W
                                    + (R - 1) * (L + 8 * n / W))
            T = A + per * t + C
            F = per * t + C
            e = (A + S * t) / (R * T)
            ef = S * t / (R * F)
            cells.append(f"R={R}: step {1e3 * T:.0f} ms (transfers {1e3 * C:.1f}), "
                         f"efficiency {e:.2f}, forecasts' {ef:.2f}")
        print(f"  {label}:\n    " + "\n    ".join(cells))

# The full-state UKF shares its dense algebra (SharedGram.h, ScalapackCholesky.h), so its model
# splits rank 0's work: A' what only rank 0 does (sigma points, deviations, the correction's
# small products, sends and receives), measured at 2 ranks as the step minus forecasts, Gram
# and Cholesky; the Gram matrix: g per column on every rank, rank 0's packing, shifts and mirror
# (measured at 2 ranks), then ceil(log2 R) reduction stages (the lower triangle, 31 MB, over the
# link plus the sum, the sum measured at 2 ranks); every Cholesky
# factorisation: rank 0 packing A and unpacking L (measured), MPI's copy of rank 0's own piece
# (1/R of the one-rank move), A and L over the link, pdpotrf's
# flops shared by R and its panels broadcast ceil(log2 R) times (ScaLAPACK on one rank measured).
def ukf_shared_model(S, n, m):
    dense = {}
    for line in open(f"{out}/dense.txt"):
        mm = re.search(r"ranks (\d+).*gram ([0-9.]+) ms, reduce ([0-9.]+) ms, cholesky ([0-9.]+) ms "
                       r"\(ScaLAPACK: pdpotrf ([0-9.]+) ms, moving A and L ([0-9.]+) ms, of which "
                       r"packing ([0-9.]+) ms", line)
        if mm:
            dense[int(mm.group(1))] = [float(v) / 1e3 for v in mm.groups()[1:]]
    gram1, _, chol1, pdpotrf1, moves1, pack1 = dense[1]
    reduce2 = dense[2][1]
    total1, forecast1, _ = steps("ukf", "1x1")
    total2, forecast2, _ = steps("ukf", "2x1")
    text = open(f"{out}/runs/ukf-2x1.txt").read()
    shared = re.search(r"Gram matrix ([0-9.]+) ms .*Cholesky ([0-9.]+) ms \((\d+) factorisations?",
                       text)
    gram2, chol2 = float(shared.group(1)) / 1e3, float(shared.group(2)) / 1e3
    c = int(shared.group(3)) / steps_of("ukf", "2x1")
    T1, F1, T2, F2 = total1 / 1e3, forecast1 / 1e3, total2 / 1e3, forecast2 / 1e3
    t, g = F1 / S, gram1 / S
    A = max(T2 - F2 - gram2 - chol2, 0.0)
    half = 8 * n * (n + 1) / 2  # bytes of the lower triangle, as it travels
    stage_sum = max(reduce2 - half / bandwidth, 0.0)
    # rank 0's own part beyond its block's Gram and the reduction: packing, shifts, mirror
    gram0 = max(gram2 - math.ceil(S / 2) * g - reduce2, 0.0)
    print(f"\nukf model (shared algebra): S {S}, n {n}, m {m}, t {1e3 * t:.3f} ms per sigma point, "
          f"A' {1e3 * A:.1f} ms rank 0's own work (2x1 step {1e3 * T2:.0f} - forecasts "
          f"{1e3 * F2:.0f} - Gram {1e3 * gram2:.0f} - Cholesky {1e3 * chol2:.0f}), Gram "
          f"{1e3 * g:.3f} ms per column, reduction's sum {1e3 * stage_sum:.1f} ms per stage, rank 0's "
          f"packing, shifts and mirror {1e3 * gram0:.0f} ms, "
          f"{c:.1f} factorisations per step, ScaLAPACK on one rank {1e3 * pdpotrf1:.0f} ms "
          f"(LAPACK {1e3 * chol1:.0f}), moving A and L on one rank {1e3 * moves1:.0f} ms, of which "
          f"packing {1e3 * pack1:.0f} ms")
    for label, L, W in [("this machine (shared memory)", latency, bandwidth),
                        ("cluster (L 2 us, W 12 GB/s: 100 Gb/s InfiniBand)", 2e-6, 12e9),
                        ("cluster (L 20 us, W 1.25 GB/s: 10 Gb/s Ethernet)", 20e-6, 1.25e9)]:
        cells = []
        for R in [2, 8, 64, 512]:
            per = math.ceil(S / R)
            busy = min(R, S)
            stages = math.ceil(math.log2(R))
            C = (3 * (busy - 1) * L + (8 * n + 8 * (n + m)) * (S - per) / W
                 + (R - 1) * (L + 8 * n / W))
            gram = per * g + gram0 + stages * (L + half / W + stage_sum)
            # rank 0 packs and unpacks every piece; MPI copies its own 1/R; the rest crosses the link
            chol = (pack1 + (moves1 - pack1) / R + 2 * 8 * n * n * (R - 1) / (R * W) + pdpotrf1 / R
                    + math.ceil(n / 128) * stages * (2 * L + 8 * n * 128 / (math.sqrt(R) * W)))
            T = A + per * t + gram + c * chol + C
            cells.append(f"R={R}: step {1e3 * T:.0f} ms (forecasts {1e3 * per * t:.0f}, Gram "
                         f"{1e3 * gram:.0f}, Cholesky {1e3 * c * chol:.0f}, transfers {1e3 * C:.1f}), "
                         f"efficiency {T1 / (R * T):.2f}")
        print(f"  {label}:\n    " + "\n    ".join(cells))
    print(f"  measured at 2x1 on this machine: step {1e3 * T2:.0f} ms, efficiency {T1 / (2 * T2):.2f}")

ukf_shared_model(2792, 2791, 45)
# The liver: positions and velocities of every node and P spring groups, P + 1 simplex points.
scene_line = open(f"{out}/runs/liver-1x1.txt").read()
nodes, markers, P = map(int, re.search(
    r": (\d+) nodes, (\d+) markers, \d+ validation points, (\d+) parameters", scene_line).groups())
model("liver", P + 1, 6 * nodes + P, 3 * markers)
PY
