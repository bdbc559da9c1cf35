#!/usr/bin/env bash
# pipeline-tracked (thesis §5.3 with synthetic tracked tackers) on five CT livers at full size:
# `bcassim liver tracked` on each (atlas built without it, truth ~14,000 nodes, 400 steps), then
# the markdown table of docs/results.md. Resumable: a liver whose summary.csv exists is skipped,
# the others continue with --resume (the atlas from its folder, the truth from its checkpoint).
# Usage, from the repository root:
#   examples/pipeline-tracked/run_livers.sh [BUILD_DIR] [OUT_DIR]
# OBSERVE=surface: the point-cloud variant (a partial surface instead of tackers); ATLAS_FROM=DIR
# takes each liver's left-out atlas from DIR/LIVER/atlas (e.g. the tacker run's) instead of
# building it again.
set -euo pipefail
BUILD=${1:-build}
OBSERVE=${OBSERVE:-tackers}
OUT=${2:-out/pipeline-tracked$([ "$OBSERVE" = surface ] && echo -surface)}
LIVERS=${LIVERS:-"LiTS-3 LiTS-10 LiTS-11 3Dircadb-18 LiTS-0"}
# Extra options for every run, e.g. OPTIONS="--fine-nodes 6000 --steps 300 --observed-steps 225".
read -r -a OPTS <<< "${OPTIONS:-}"
mkdir -p "$OUT"
for liver in $LIVERS; do
  if [ -f "$OUT/$liver/summary.csv" ]; then echo "$liver: done already"; continue; fi
  atlas=()
  if [ -n "${ATLAS_FROM:-}" ] && [ -d "$ATLAS_FROM/$liver/atlas" ]; then
    atlas=(--atlas "$ATLAS_FROM/$liver/atlas")
  fi
  start=$SECONDS
  "$BUILD/bcassim" liver tracked "$liver" --out "$OUT/$liver" -q --resume --observe "$OBSERVE" \
    "${atlas[@]}" "${OPTS[@]}" >> "$OUT/$liver.log" 2>&1 ||
    { echo "$liver failed: see $OUT/$liver.log"; continue; }
  echo "$liver done ($((SECONDS - start)) s)"
done
echo
if [ "$OBSERVE" = surface ]; then
  echo "| liver | area seen, points per frame | registration error mean / max (mm) | springs' curve to expert (mm) | (i) vessels TRE peak / over steps (mm) | (ii) + atlas springs, prior | (iii) + springs estimated | fiducials' peak displacement (mm) | step (ms) |"
else
  echo "| liver | tracks / tackers, switches | registration error mean / max (mm) | springs' curve to expert (mm) | (i) vessels TRE peak / over steps (mm) | (ii) + atlas springs, prior | (iii) + springs estimated | fiducials' peak displacement (mm) | step (ms) |"
fi
echo "|---|---|---|---|---|---|---|---|---|"
for liver in $LIVERS; do
  s="$OUT/$liver/summary.csv"
  [ -f "$s" ] || continue
  python3 - "$s" "$liver" <<'PY'
import csv, re, sys
lines = open(sys.argv[1]).read().splitlines()
rows = {r["scenario"]: r for r in csv.DictReader(l for l in lines if not l.startswith("#"))}
notes = " ".join(l for l in lines if l.startswith("#"))
num = lambda pattern: float(re.search(pattern, notes).group(1))
cell = lambda r: f"{float(rows[r]['tre_peak_mean_mm']):.2f} / {float(rows[r]['tre_mean_mm']):.2f}"
if "# surface camera" in notes:
    area, per_frame = num(r"surface camera: ([0-9.e+-]+) of the area"), num(r"(\d+) points per frame")
    seen = f"{100 * area:.0f} %, {int(per_frame)}"
else:
    tackers, tracks, switches = (int(num(p)) for p in (r"(\d+) tackers", r"(\d+) tracks", r"(\d+) switches"))
    seen = f"{tracks} / {tackers}, {switches}"
print(f"| {sys.argv[2]} | {seen} "
      f"| {num(r'error mean ([0-9.e+-]+) mm'):.2f} / {num(r'error mean [0-9.e+-]+ mm max ([0-9.e+-]+) mm'):.2f} "
      f"| {num(r'expert.s: mean ([0-9.e+-]+) mm'):.1f} "
      f"| {cell('vessels')} | {cell('prior')} | {cell('estimated')} "
      f"| {num(r'mean displacement ([0-9.e+-]+) mm'):.1f} | {num(r'median step ([0-9.e+-]+) ms'):.0f} |")
PY
done
