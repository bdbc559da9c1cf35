#!/usr/bin/env bash
# Atlas mode against annotation mode on five CT livers (issue 16 point 4, thesis §5.3's three
# scenarios on our livers): one ligament atlas built from other annotated livers (none of the
# five: each is left out), then `bcassim liver run` on each liver twice, with its springs on its
# expert curve and on the atlas' curve, and the markdown table of docs/results.md. Usage, from the
# repository root:
#   examples/liver/run_atlas_mode.sh [BUILD_DIR] [OUT_DIR]
# ATLAS_LIVERS (default 20): how many other livers build the atlas; OPTIONS: options of every run
# (default the demo's reduced truth: 5,000 nodes, 250 steps, 200 observed). Resumable: a run whose
# summary.csv exists is skipped, a complete atlas is reused.
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/liver-atlas-mode}
DATA=${BCASSIM_DATA:-../shared/data}
LIVERS=${LIVERS:-"LiTS-3 LiTS-10 LiTS-11 3Dircadb-18 LiTS-0"}
ATLAS_LIVERS=${ATLAS_LIVERS:-20}
read -r -a OPTS <<< "${OPTIONS:---fine-nodes 5000 --steps 250 --observed-steps 200}"
B="$BUILD/bcassim"
mkdir -p "$OUT"
read -r -a LEFT_OUT <<< "$LIVERS"
if [ ! -f "$OUT/atlas/template.obj" ]; then
  "$B" atlas build "$DATA/livers" --exclude "${LEFT_OUT[@]}" --max-livers "$ATLAS_LIVERS" \
    --centre trimmed --out "$OUT/atlas.partial" > "$OUT/atlas.log" 2>&1
  rm -rf "$OUT/atlas" && mv "$OUT/atlas.partial" "$OUT/atlas"
fi
for liver in $LIVERS; do
  for mode in annotation atlas; do
    dir="$OUT/$liver-$mode"
    [ -f "$dir/summary.csv" ] && continue
    extra=()
    [ "$mode" = atlas ] && extra=(--atlas "$OUT/atlas")
    "$B" liver run "$liver" --out "$dir" -q --no-plots --no-picture "${OPTS[@]}" "${extra[@]}" \
      > "$dir.log" 2>&1 || { echo "$liver $mode failed: see $dir.log"; continue; }
    echo "$liver $mode done"
  done
done
echo
echo "| liver | springs' curve from the expert's: mean / max (mm) | annotation: estimated / prior / fixed (mm) | atlas: estimated / prior / fixed (mm) | atlas / annotation estimated |"
echo "|---|---|---|---|---|"
for liver in $LIVERS; do
  python3 - "$OUT/$liver-annotation/summary.csv" "$OUT/$liver-atlas/summary.csv" "$liver" <<'PY'
import csv, os, re, sys
def read(path):
    if not os.path.exists(path):
        return None, []
    lines = open(path).read().splitlines()
    rows = {r["model"]: float(r["mean_error_mm"]) for r in csv.DictReader(l for l in lines if not l.startswith("#"))}
    return rows, [l for l in lines if l.startswith("#")]
ann, _ = read(sys.argv[1])
atl, notes = read(sys.argv[2])
if ann is None or atl is None:
    print(f"| {sys.argv[3]} | (not run) | | | |"); sys.exit()
d = next((re.search(r"mean (\S+) mm, max (\S+) mm", l) for l in notes if "atlas mode" in l), None)
dist = f"{float(d.group(1)):.1f} / {float(d.group(2)):.1f}" if d else "undefined"
f = lambda r: f"{r['estimated']:.2f} / {r['prior']:.2f} / {r['fixed']:.2f}"
print(f"| {sys.argv[3]} | {dist} | {f(ann)} | {f(atl)} | {atl['estimated'] / ann['estimated']:.2f} |")
PY
done
