#!/usr/bin/env bash
# `make demo`: the product's main job end to end with the Release build in $1 (default build/):
# the liver experiment of thesis §5.1 on a real CT liver from the data directory (BCASSIM_DATA,
# default ../shared/data), or on the built-in phantom when the data is absent. It meshes the
# liver, runs a ground truth, estimates the falciform ligament's spring stiffnesses from 14
# tracked markers with ROUKF, validates against a fixed-ligament baseline at 12 inner points,
# predicts 3 tumours with their uncertainty, and writes CSVs, a ParaView series, PNG plots and a
# rendered picture into out/liver. Sizes are reduced (truth 5,000 nodes, 250 steps) to keep the
# demo to a few minutes; `bcassim liver run LiTS-3 --out DIR` runs the full-size experiment.
set -euo pipefail
BUILD=${1:-build}
cd "$(dirname "$0")/.."
DATA=${BCASSIM_DATA:-../shared/data}
LIVER=${BCASSIM_DEMO_LIVER:-LiTS-3}
if [ -f "$DATA/livers/$LIVER.obj" ]; then
  echo "bcassim demo: liver $LIVER from $DATA/livers"
  export BCASSIM_DATA="$DATA"
else
  echo "bcassim demo: no liver data at $DATA/livers. The CT livers come from the 3D-IRCADb-01 and"
  echo "  LiTS data sets with falciform annotations of the TSMCN project (see docs/liver.md);"
  echo "  set BCASSIM_DATA to their directory. Running on the built-in liver phantom instead."
  LIVER=phantom
fi
RUN=("$BUILD/bcassim")
if [ -z "${DISPLAY:-}" ]; then
  if command -v xvfb-run > /dev/null; then
    RUN=(xvfb-run -a "$BUILD/bcassim")
  else
    echo "bcassim demo: no X display and no xvfb-run: the picture will be skipped (apt-get install xvfb)"
  fi
fi
mkdir -p out
"${RUN[@]}" liver run "$LIVER" --out out/liver --fine-nodes 5000 --steps 250 --observed-steps 200

# Live: the same estimation served over OpenIGTLink in the asynchronous mode, its truth tracks
# replayed at 30 Hz as a camera would send them (docs/live.md).
echo "bcassim demo: live, the estimation served over OpenIGTLink (bcassim serve --async), the tracks replayed at 30 Hz:"
rm -rf out/liver/served
"$BUILD/bcassim" serve out/liver/estimate.yaml --async --port 0 --out out/liver/served \
  --idle-timeout 30 > out/liver/serve.out 2> out/liver/serve.log &
server=$!
for _ in $(seq 600); do grep -q '^serving' out/liver/serve.out 2>/dev/null && break; sleep 0.1; done
port=$(sed -n 's/^serving .* on 127\.0\.0\.1:\([0-9]*\) .*/\1/p' out/liver/serve.out)
"$BUILD/bcassim" replay out/liver/truth/markers.csv --to "127.0.0.1:$port" --rate 30 > out/liver/replay.out
wait $server
grep -E '^(latency|asynchronous|filter)' out/liver/serve.out | sed 's/^/  /'
echo "  to watch it in 3D Slicer: docs/live.md (bcassim serve + Slicer's OpenIGTLinkIF)"
echo "bcassim demo: picture out/liver/liver.png; plots out/liver/*.png and out/liver/estimate/*.png;"
echo "  open out/liver/truth/simulation.pvd and out/liver/estimated/simulation.pvd in ParaView."
