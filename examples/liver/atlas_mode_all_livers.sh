#!/usr/bin/env bash
# `bcassim liver prepare --atlas` on every shared liver (issue 16 point 4: atlas mode works on
# each): the meshes (the estimation mesh at its default size, a small truth), the atlas curve
# transferred and the springs placed;
# prints one line per liver (the template's rotation, the curve's distance from the expert's) and
# the count of livers that failed. Usage, from the repository root:
#   examples/liver/atlas_mode_all_livers.sh BUILD_DIR ATLAS_DIR [OUT_DIR]
# ATLAS_DIR: an atlas of `bcassim atlas build` (e.g. out/liver-atlas-mode/atlas of
# run_atlas_mode.sh); livers it was built from are marked "in atlas" (their distance is not a
# leave-one-out one). ATLAS_DIR "-": annotation mode (springs on each liver's .eseg), the same
# meshes. Resumable: a liver whose log is complete is skipped.
set -uo pipefail
BUILD=${1:?build folder}
ATLAS=${2:?atlas folder}
OUT=${3:-out/liver-atlas-all}
DATA=${BCASSIM_DATA:-../shared/data}
mkdir -p "$OUT"
failed=0
for obj in "$DATA"/livers/*.obj; do
  liver=$(basename "$obj" .obj)
  log="$OUT/$liver.log"
  if ! grep -q '^next:' "$log" 2> /dev/null; then
    mode=(--atlas "$ATLAS")
    [ "$ATLAS" = - ] && mode=()
    "$BUILD/bcassim" liver prepare "$obj" "${mode[@]}" --out "$OUT/$liver" \
      --fine-nodes 2500 > "$log" 2>&1 || true
  fi
  if grep -q '^next:' "$log"; then
    turn=$(sed -n 's/.*template turned \([0-9.]*\) deg.*/\1/p' "$log")
    dist=$(sed -n 's/.*expert.s curve: mean \([0-9.]*\) mm, max \([0-9.]*\) mm.*/\1 \/ \2/p' "$log")
    inatlas=""
    cut -d, -f2 "$ATLAS/subjects.csv" 2> /dev/null | grep -qx "$liver" && inatlas=" (in atlas)"
    echo "| $liver | ok | ${turn:-?} | ${dist:-undefined} |$inatlas"
  else
    failed=$((failed + 1))
    echo "| $liver | FAILED: $(tail -1 "$log") | | |"
  fi
done
echo "failed: $failed"
