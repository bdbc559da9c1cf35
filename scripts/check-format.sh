#!/usr/bin/env bash
# Checks that every C++ file of the project (tracked, or new and not ignored) is formatted as
# .clang-format says; lists the ones that are not and fails. With --fix, formats them in place.
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
[ "${1:-}" = "--fix" ] && fix=1
command -v clang-format >/dev/null || { echo "check-format: clang-format not found (make deps)" >&2; exit 1; }
mapfile -t files < <( (git ls-files '*.cpp' '*.h'; git ls-files --others --exclude-standard '*.cpp' '*.h') | sort -u)
bad=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if [ $fix -eq 1 ]; then
    clang-format -i --style=file "$f"
  elif ! clang-format --style=file "$f" | cmp -s - "$f"; then
    bad+=("$f")
  fi
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "check-format: ${#bad[@]} of ${#files[@]} files differ from .clang-format; run scripts/check-format.sh --fix:" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
[ $fix -eq 1 ] || echo "check-format: ${#files[@]} files formatted as .clang-format says"
