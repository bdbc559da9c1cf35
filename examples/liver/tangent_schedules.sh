#!/usr/bin/env bash
# How old may the mean's tangent be? The estimation of finished `bcassim liver run` folders run
# again (`bcassim assimilate`, then `bcassim validate` with its final parameters) under several
# tangent schedules and observation-noise seeds, the truth reused; prints the markdown table of
# docs/liver.md ("How old a tangent may be"). Usage, from the repository root:
#   examples/liver/tangent_schedules.sh BUILD_DIR OUT_DIR RUN_DIR...
# RUN_DIR: the --out of a `bcassim liver run` (its truth/ is read, and the variant scenes are
# written beside its estimate.yaml, whose relative paths they keep: tangent-<schedule>-s<seed>.yaml).
# SEEDS (default "1 2 3 4 5"): assimilation.seed of each rerun (the observation noise).
# SCHEDULES (default "2/1 2/2 1/sync"): refresh/steps, i.e. tangent_refresh_every and
# tangent_background_steps ("sync": built at the end of each step, no background thread).
# A run that stops (a step of the estimation or of its validation that fails) is counted as such
# in the table, its error in OUT/LIVER/SCHEDULE-sSEED/{assimilate,validate}.log. Resumable: a
# variant that finished or failed is skipped.
set -euo pipefail
BUILD=$1
OUT=$2
shift 2
SEEDS=${SEEDS:-"1 2 3 4 5"}
SCHEDULES=${SCHEDULES:-"2/1 2/2 1/sync"}
B="$BUILD/bcassim"
mkdir -p "$OUT"
for run in "$@"; do
  if [ ! -f "$run/estimate.yaml" ] || [ ! -f "$run/truth/markers.csv" ]; then
    echo "$run: not a finished \`bcassim liver run\` folder (estimate.yaml, truth/markers.csv)" >&2
    exit 1
  fi
  liver=$(basename "$run")
  for schedule in $SCHEDULES; do
    tag=${schedule/\//-}
    for seed in $SEEDS; do
      dir="$OUT/$liver/$tag-s$seed"
      [ -f "$dir/done" ] || [ -f "$dir/failed" ] && continue
      scene="$run/tangent-$tag-s$seed.yaml"
      python3 - "$run/estimate.yaml" "$scene" "$schedule" "$seed" <<'PY'
import re, sys
src, dst, schedule, seed = sys.argv[1:]
refresh, steps = schedule.split("/")
text = open(src).read()
# The assimilation section's keys sit at two spaces; drop those the schedule sets.
text = re.sub(r"\n  (tangent_background|tangent_refresh_every|tangent_background_steps|seed):[^\n]*",
              "", text)
keys = [f"tangent_refresh_every: {refresh}"]
if steps == "sync":
    keys.append("tangent_background: false")
else:
    keys += ["tangent_background: true", f"tangent_background_steps: {steps}"]
keys.append(f"seed: {seed}")
text, n = re.subn(r"(\n  tangent: mean[^\n]*)", lambda m: m.group(1) + "".join(
    "\n  " + k for k in keys), text)
if n != 1:
    sys.exit(f"{src}: expected one 'tangent: mean' line in its assimilation section, found {n}")
open(dst, "w").write(text)
PY
      mkdir -p "$dir"
      if ! "$B" assimilate "$scene" --out "$dir/estimate" -q --no-plots > "$dir/assimilate.log" 2>&1
      then
        tail -n 1 "$dir/assimilate.log" > "$dir/failed"
        continue
      fi
      # A validation that stops (the forward run with the final estimates fails) counts as a
      # stopped run too, its line kept; the other variants go on.
      if ! "$B" validate "$scene" --estimates "$dir/estimate/estimates.csv" --out "$dir/validate" \
        -q --no-plots > "$dir/validate.log" 2>&1; then
        tail -n 1 "$dir/validate.log" > "$dir/failed"
        continue
      fi
      touch "$dir/done"
    done
  done
done
python3 - "$OUT" "$SCHEDULES" <<'PY'
import csv, glob, os, re, statistics, sys
out, schedules = sys.argv[1], sys.argv[2].split()
rows, failed = {}, {}
# Each variant's folder OUT/LIVER/SCHEDULE-sSEED: stopped (its `failed` mark, counted), or the
# validation's mean error over all steps with the final estimates, from the file `validate`
# writes for it (errors_summary.csv: run "estimated", phase "all").
for variant in glob.glob(os.path.join(out, "*", "*-s*")):
    liver = os.path.basename(os.path.dirname(variant))
    tag = re.match(r"(.*)-s\d+$", os.path.basename(variant)).group(1)
    rows.setdefault(liver, {})
    summary = os.path.join(variant, "validate", "errors_summary.csv")
    if os.path.exists(os.path.join(variant, "failed")):
        failed[(liver, tag)] = failed.get((liver, tag), 0) + 1
    elif os.path.exists(summary):
        for r in csv.DictReader(open(summary)):
            if r["run"] == "estimated" and r["phase"] == "all":
                rows[liver].setdefault(tag, []).append(float(r["mean_mm"]))
def label(s):
    refresh, steps = s.split("/")
    return f"refresh {refresh}, " + (
        "built at the step's end" if steps == "sync" else f"adopted after {steps}")
print("| liver | " + " | ".join(label(s) for s in schedules) + " |")
print("|---|" + "---|" * len(schedules))
for liver in sorted(rows):
    cells = []
    for s in schedules:
        tag = s.replace("/", "-")
        v = rows[liver].get(tag, [])
        seeds = f"{len(v)} seed" + ("s" if len(v) > 1 else "")
        cell = f"{statistics.mean(v):.2f} ({min(v):.2f}–{max(v):.2f}, {seeds})" if v else "—"
        stopped = failed.get((liver, tag), 0)
        cells.append(cell + (f"; {stopped} stopped" if stopped else ""))
    print(f"| {liver} | " + " | ".join(cells) + " |")
PY
