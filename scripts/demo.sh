#!/usr/bin/env bash
# `make demo`: runs the default scenario end to end with the Release build in $1 (default build/).
# Today that is the cylinder of thesis §3.4 (StVK, periodic force, 15 surface markers); the liver
# estimation takes its place once the liver pipeline lands.
set -euo pipefail
BUILD=${1:-build}
cd "$(dirname "$0")/.."
DATA=${BCASSIM_DATA:-../shared/data}
if [ -d "$DATA" ]; then
  echo "bcassim demo: data directory $DATA found (used by the liver scenes)."
else
  echo "bcassim demo: no data directory at $DATA. The real livers come from the 3D-IRCADb-01 and"
  echo "  LiTS data sets (annotated by the TSMCN project); set BCASSIM_DATA to use them."
fi
mkdir -p out
echo "bcassim demo: simulating examples/cylinder/cylinder.yaml -> out/cylinder"
"$BUILD/bcassim" simulate examples/cylinder/cylinder.yaml --out out/cylinder
echo "bcassim demo: open out/cylinder/simulation.pvd in ParaView; marker tracks in out/cylinder/markers.csv"
