#!/usr/bin/env bash
# Leave-one-out with the thesis' own atlas (eq. 4.8) in every fold: for each held-out liver, a
# Frechet-mean atlas is built from the 54 others (template shape and curves; the held-out surface
# and curve never enter it), then transferred onto the held-out liver and compared with its
# expert curve. The options were fixed before any run (--centre trimmed, --project: recommended in
# docs/results-atlas.md at no extra cost); the held-out livers come in sets of 11 by their sorted
# index mod 5, each declared before it was run (docs/results-atlas.md): 2 (the planned set), 4, 0.
#
#   examples/atlas-loo/frechet-folds.sh [BCASSIM] [LIVER_DIR] [OUT] [RESIDUES]   # ~2.5 min per fold
#
# RESIDUES (default 2,4,0): held-out livers are those whose sorted index mod 5 is in this
# comma-separated list; the results page uses 2,4,0 (33 livers, 70 min).
#
# ATLAS_OPTIONS (default empty): more options of `atlas build`, e.g. "--ridge" (the multi-object
# data term). TRANSFER_RIDGE=1: the transfer matches the held-out liver's ridge (its .eseg label 3,
# never its falciform) with the atlas template's, as for a patient whose ridge is labelled.
#
# Writes OUT/folds.csv (liver, planes, mean_mm, max_mm, and the same against the expert's whole
# annotated band) and prints the mean over the folds. A fold whose result is already in
# OUT/folds.csv is skipped, so an interrupted run resumes.
set -euo pipefail
bcassim=${1:-build/bcassim}
livers=${2:-../shared/data/livers}
out=${3:-out/atlas-frechet-folds}
residues=",${4:-2,4,0},"
sigma_w=0.02   # m, data-term kernel width (docs/results-atlas.md)

mkdir -p "$out"
csv="$out/folds.csv"
[[ -f "$csv" ]] || echo "liver,planes,mean_mm,max_mm,band_planes,band_mean_mm,band_max_mm" >"$csv"
read -r -a atlas_options <<<"${ATLAS_OPTIONS:-}"
run=()
[[ -z "${DISPLAY:-}" ]] && command -v xvfb-run >/dev/null && run=(xvfb-run -a)

mapfile -t names < <(ls "$livers"/*.obj | xargs -n1 basename | sed 's/\.obj$//' | LC_ALL=C sort)
for i in "${!names[@]}"; do
  [[ "$residues" == *",$((i % 5)),"* ]] || continue
  name=${names[$i]}
  grep -q "^$name," "$csv" && { echo "$name: done already"; continue; }
  fold="$out/$name"
  ridge_option=()
  [[ -n "${TRANSFER_RIDGE:-}" ]] && ridge_option=(--ridge-from "$livers/$name.eseg")
  start=$SECONDS
  "${run[@]}" "$bcassim" atlas build "$livers" --exclude "$name" --sigma-w $sigma_w \
      --centre trimmed "${atlas_options[@]}" --out "$fold/atlas" >"$fold.build.log" 2>&1
  "${run[@]}" "$bcassim" atlas transfer "$fold/atlas" "$livers/$name.obj" --eseg "$livers/$name.eseg" \
      --sigma-w $sigma_w --iterations 100 --project --out "$fold/transfer" \
      "${ridge_option[@]}" >"$fold.transfer.log" 2>&1
  line=$(grep "distance to the expert curve" "$fold.transfer.log" || true)
  planes=$(sed -E 's/.*planes ([0-9]+) .*/\1/' <<<"${line:-planes 0 }")
  if [[ "$planes" == 0 ]]; then
    echo "$name: no plane shared with the expert curve (see $fold.transfer.log)"
    echo "$name,0,," >>"$csv"
    continue
  fi
  mean=$(sed -E 's/.* mean ([0-9.]+) mm max ([0-9.]+) mm;.*/\1/' <<<"$line")
  max=$(sed -E 's/.* mean ([0-9.]+) mm max ([0-9.]+) mm;.*/\2/' <<<"$line")
  band=$(grep "whole band" "$fold.transfer.log" || true)
  band_fields=",,"
  if [[ "$band" == *" mean "* ]]; then
    band_fields=$(sed -E 's/.*planes ([0-9]+) mean ([0-9.]+) mm max ([0-9.]+) mm;.*/\1,\2,\3/' <<<"$band")
  fi
  echo "$name,$planes,$mean,$max,$band_fields" >>"$csv"
  echo "$name: $planes planes, mean $mean mm, max $max mm; band $band_fields ($((SECONDS - start)) s)"
done

awk -F, 'NR > 1 && $3 != "" { n++; m += $3; x += $4 }
         NR > 1 && $6 != "" { nb++; b += $6 }
         END { if (n) printf "folds %d: mean %.1f mm, mean of max %.1f mm\n", n, m / n, x / n
               if (nb) printf "against the whole band, folds %d: mean %.1f mm\n", nb, b / nb }' "$csv"
