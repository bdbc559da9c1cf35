#!/usr/bin/env bash
# clang-tidy (.clang-tidy: bugprone-*, performance-*, warnings as errors) on every .cpp of src/,
# with the compile commands of a configured build folder, one process per core; prints the
# findings and fails on any.
# Usage: scripts/run-clang-tidy.sh [BUILD_DIR] [FILE...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
[ -f "$build/compile_commands.json" ] || {
  echo "run-clang-tidy: $build/compile_commands.json missing (configure first: make configure)" >&2
  exit 1
}
command -v clang-tidy >/dev/null || { echo "run-clang-tidy: clang-tidy not found (make deps)" >&2; exit 1; }
if [ $# -gt 0 ]; then
  files=("$@")
else
  mapfile -t files < <( (git ls-files 'src/*.cpp'; git ls-files --others --exclude-standard 'src/*.cpp') | sort -u)
fi
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
export build logs
printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -I{} bash -c '
  log="$logs/$(echo "$1" | tr / _).log"
  clang-tidy -p "$build" --quiet "$1" > "$log" 2>&1 || touch "$log.failed"' _ {}
failed=0
for f in "${files[@]}"; do
  log="$logs/$(echo "$f" | tr / _).log"
  if [ -e "$log.failed" ]; then
    failed=$((failed + 1))
    grep -E "^/.*(warning|error):" "$log" || cat "$log"
  fi
done
if [ $failed -gt 0 ]; then
  echo "run-clang-tidy: findings in $failed of ${#files[@]} files" >&2
  exit 1
fi
echo "run-clang-tidy: ${#files[@]} files clean"
