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
# The UKF's dense algebra alone and kept over 1 and 2 ranks, one BLAS thread per rank.
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

# The full-state UKF keeps its covariance over the ranks (UkfCovarianceShare.h): every rank forms
# its own sigma points from its columns of the factor, forecasts them, adds their Gram matrix into
# the block-cyclic pieces and applies the Kalman update to its piece; rank 0 keeps only vectors and
# m x S matrices. Per step on R ranks:
#   T(R) = A + ceil(S/R) (t + g + p) + K(R) + X(R) + Gr(R) + Cr(R) + C(R)
# A what only rank 0 does (observations, Pz, H, the diagonal, the mean's end of step), measured at
# 2x1 as the step minus rank 0's parts; t one sigma point's forecast, g its Gram products and p its
# point (bench_dense_algebra on one rank, per column); K the factorisation: ScaLAPACK's flops on
# one rank shared by R and its panels broadcast down a tree; X the factor's columns: each rank's
# n x S/R share over the link, its copies (one rank's measured, / R) and the suffix sums'
# reduce-scatter (n R doubles); Gr the Gram matrix's reduce-scatter of the packed lower triangle
# (ring: (R-1)/R of it over each link and summed, the sum per byte measured at 2 ranks, the
# reduce-scatter alone with every rank ready) and the
# mean's reduce and broadcast; Cr the correction: H's columns scattered, the products (measured on
# one rank) shared by R, G reduced and broadcast; C rank 0's messages (the commands, the mean out
# twice, the observables back).
def ukf_shared_model(S, n, m):
    dense = {}
    for line in open(f"{out}/dense.txt"):
        mm = re.search(r"ranks (\d+).*alone \(rank 0\) gram ([0-9.]+) ms, cholesky ([0-9.]+) ms, "
                       r"sigma points ([0-9.]+) ms, update ([0-9.]+) ms; kept over the ranks: draw "
                       r"([0-9.]+) ms \(factor ([0-9.]+), pdpotrf ([0-9.]+), factor's columns "
                       r"([0-9.]+), own points ([0-9.]+)\), mean and gram ([0-9.]+) ms \(products "
                       r"([0-9.]+), reduce-scatter ([0-9.]+)\), correction ([0-9.]+) ms; "
                       r"reduce-scatter alone ([0-9.]+) ms", line)
        if mm:
            keys = ["gram", "chol", "points", "update", "draw", "factor", "pdpotrf", "columns",
                    "own", "moments", "products", "reduce", "correct", "reduce_alone"]
            dense[int(mm.group(1))] = dict(zip(keys, (float(v) / 1e3 for v in mm.groups()[1:])))
    one, two = dense[1], dense[2]
    total1, forecast1, _ = steps("ukf", "1x1")
    total2, forecast2, _ = steps("ukf", "2x1")
    text = open(f"{out}/runs/ukf-2x1.txt").read()
    kept = re.search(r"Cholesky ([0-9.]+) ms \(pdpotrf ([0-9.]+)\), factor's columns ([0-9.]+) ms, "
                     r"own sigma points ([0-9.]+) ms, mean and Gram matrix ([0-9.]+) ms \(products "
                     r"([0-9.]+), reduce-scatter ([0-9.]+)\), correction ([0-9.]+) ms", text)
    chol2, _, columns2, points2, gram2, _, _, corr2 = (float(v) / 1e3 for v in kept.groups())
    T1, F1, T2, F2 = total1 / 1e3, forecast1 / 1e3, total2 / 1e3, forecast2 / 1e3
    # The 1x1 forecasts time includes rank 0's factor and sigma points (the threaded filter's).
    t = max(F1 - one["chol"] - one["points"], 0.0) / S
    g, p = one["products"] / S, one["own"] / S
    A = max(T2 - F2 - gram2 - corr2, 0.0)
    half = 8 * n * (n + 1) / 2  # bytes of the packed lower triangle, about
    # A ring reduce-scatter: (R-1)/R of the matrix over each link and summed; at 2 ranks, half.
    sum_per_byte = max(two["reduce_alone"] - half / 2 / bandwidth, 0.0) / (half / 2)
    print(f"\nukf model (covariance kept over the ranks): S {S}, n {n}, m {m}, t {1e3 * t:.3f} ms "
          f"per sigma point, Gram products {1e3 * g:.3f} ms and point {1e3 * p:.4f} ms per column, "
          f"A {1e3 * A:.1f} ms rank 0's own work (2x1 step {1e3 * T2:.0f} - forecasts "
          f"{1e3 * F2:.0f} - mean and Gram {1e3 * gram2:.0f} - correction {1e3 * corr2:.0f}; rank "
          f"0's Cholesky {1e3 * chol2:.0f}, factor's columns {1e3 * columns2:.0f}, points "
          f"{1e3 * points2:.0f} inside its forecasts), ScaLAPACK on one rank "
          f"{1e3 * one['pdpotrf']:.0f} ms (LAPACK {1e3 * one['chol']:.0f}), factor's columns on one "
          f"rank {1e3 * one['columns']:.0f} ms, reduce-scatter's sum {1e9 * sum_per_byte:.2f} ns/B, "
          f"correction on one rank {1e3 * one['correct']:.0f} ms")
    for label, L, W in [("this machine (shared memory)", latency, bandwidth),
                        ("cluster (L 2 us, W 12 GB/s: 100 Gb/s InfiniBand)", 2e-6, 12e9),
                        ("cluster (L 20 us, W 1.25 GB/s: 10 Gb/s Ethernet)", 20e-6, 1.25e9)]:
        cells = []
        for R in [2, 8, 64, 512]:
            per = math.ceil(S / R)
            tree = math.ceil(math.log2(R))
            K = one["pdpotrf"] / R + math.ceil(n / 128) * tree * (
                2 * L + 8 * n * 128 / (math.sqrt(R) * W))
            X = one["columns"] / R + 8 * n * per / W + (R - 1) * L + 8 * n * (R - 1) / W
            Gr = (R - 1) / R * half * (1 / W + sum_per_byte) + (R - 1) * L + 2 * tree * (L + 8 * n / W)
            Cr = (one["correct"] / R + 8 * m * S * (R - 1) / (R * W) + (R - 1) * L
                  + 2 * tree * (L + 8 * m * n / W))
            C = (R - 1) * (8 * L + 2 * 8 * n / W) + 8 * m * (S - per) / W
            T = A + per * (t + g + p) + K + X + Gr + Cr + C
            cells.append(f"R={R}: step {1e3 * T:.0f} ms (forecasts {1e3 * per * t:.0f}, Gram "
                         f"{1e3 * (per * g + Gr):.0f}, Cholesky {1e3 * K:.0f}, factor's columns and "
                         f"points {1e3 * (X + per * p):.0f}, correction {1e3 * Cr:.0f}, rank 0's "
                         f"messages {1e3 * C:.1f}), efficiency {T1 / (R * T):.2f}")
        print(f"  {label}:\n    " + "\n    ".join(cells))
    print(f"  measured at 2x1 on this machine: step {1e3 * T2:.0f} ms, efficiency {T1 / (2 * T2):.2f}")

ukf_shared_model(2792, 2791, 45)
# The liver: positions and velocities of every node and P spring groups, P + 1 simplex points.
scene_line = open(f"{out}/runs/liver-1x1.txt").read()
nodes, markers, P = map(int, re.search(
    r": (\d+) nodes, (\d+) markers, \d+ validation points, (\d+) parameters", scene_line).groups())
model("liver", P + 1, 6 * nodes + P, 3 * markers)
PY
