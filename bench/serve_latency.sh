#!/usr/bin/env bash
# Per-frame latency of `bcassim serve` end to end on loopback: a liver's scenes prepared, its
# truth run's marker tracks replayed at 30 Hz by `bcassim replay`, and the latency of every frame
# from its last byte read by the server to its answer (hidden points, surface) leaving the socket
# (served/latency.csv), with the round trip the replaying client measured. Prints one markdown
# row for docs/benchmarks.md. The scene's validation run (a forward run of the fixed baseline per
# frame, for errors.csv) is left out (--no-validation): a live camera has no truth to compare to;
# SERVE_VALIDATION=1 keeps it.
#
#   [SERVE_OPTIONS=--async] bench/serve_latency.sh BUILD_DIR LIVER [OUT] [extra `liver prepare` options]
#   e.g. bench/serve_latency.sh build phantom out/bench/serve-phantom
#        bench/serve_latency.sh build LiTS-3 out/bench/serve-LiTS-3
set -euo pipefail
BUILD=$1
LIVER=$2
OUT=${3:-out/bench/serve-$LIVER}
shift $(($# < 3 ? $# : 3))
BCASSIM=$(cd "$BUILD" && pwd)/bcassim
export OMP_THREAD_LIMIT=${OMP_THREAD_LIMIT:-1}
mkdir -p "$OUT"
cd "$OUT"
if [ ! -f truth/markers.csv ]; then
  "$BCASSIM" liver prepare "$LIVER" --out . "$@" > prepare.out
  "$BCASSIM" simulate truth.yaml --out truth -q > truth.out
fi
rm -rf served
# shellcheck disable=SC2086
"$BCASSIM" serve estimate.yaml ${SERVE_OPTIONS:-} $([ "${SERVE_VALIDATION:-0}" = 1 ] || echo --no-validation) --port 0 --out served --idle-timeout 30 > serve.out 2> serve.log &
server=$!
for _ in $(seq 600); do grep -q '^serving' serve.out 2>/dev/null && break; sleep 0.1; done
port=$(sed -n 's/^serving .* on 127\.0\.0\.1:\([0-9]*\) .*/\1/p' serve.out)
"$BCASSIM" replay truth/markers.csv --to "127.0.0.1:$port" --rate 30 > replay.out
wait $server
cat serve.out replay.out >&2
python3 - "$LIVER" <<'PY'
import csv, sys
rows = list(csv.DictReader(open("served/latency.csv")))
ms = sorted(float(r["latency_ms"]) for r in rows)
def pct(p):
    import math
    return ms[max(0, math.ceil(p / 100 * len(ms)) - 1)]
serve = open("serve.out").read()
skipped = serve.split(" refused")[0].rsplit(", ", 1)[-1] if " refused" in serve else "?"
rt = [l for l in open("replay.out") if l.startswith("round trip")][0].split(": ", 1)[1].strip()
import os
mode = "asynchronous" if "--async" in os.environ.get("SERVE_OPTIONS", "") else "synchronous"
lags = [int(r["lag_frames"]) for r in rows]
print(f"| {sys.argv[1]} | {mode} | {len(ms)} | {pct(50):.1f} | {pct(95):.1f} | {pct(99):.1f} | {ms[-1]:.1f} "
      f"| {max(lags)} | {skipped} | {rt} |")
PY
