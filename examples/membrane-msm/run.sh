#!/usr/bin/env bash
# membrane-msm (thesis §2.3.4, Fig. 2.15-2.16, Table 2.2): the 40 x 100 x 1 mm Neo-Hookean strip
# of the thesis' softest (E 403 kPa) and stiffest (E 72 MPa) ligament samples, stretched to 45 %;
# ROUKF fits a cubic spring lattice to each, compares the two and times them side by side.
# Usage: examples/membrane-msm/run.sh [BCASSIM] [OUT]   (defaults build/bcassim, out/membrane-msm)
set -euo pipefail
bcassim=${1:-build/bcassim}
out=${2:-out/membrane-msm}
for young in 403e3 72e6; do
  echo "== E = $young Pa"
  OMP_THREAD_LIMIT=1 "$bcassim" ligament springs --material neo-hookean --young "$young" \
    --poisson 0.45 --thickness 1e-3 --width 40e-3 --length 100e-3 --strain 0.45 \
    --out "$out/E$young"
done
