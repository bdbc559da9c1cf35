#!/usr/bin/env bash
# `cmake --install` puts the Python package where Debian's python3 finds it under a prefix
# (lib/python3.X/dist-packages); installed into a scratch prefix, it imports and runs from there.
set -euo pipefail
BUILD=$1 PYTHON=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$BUILD" --prefix "$prefix" > "$prefix/install.log"
site=$(find "$prefix" -type d -name dist-packages | head -1)
test -f "$site/bcassim/__init__.py" || { echo "no bcassim package under $prefix"; exit 1; }
cd "$prefix"  # not the source or build tree
env -u PYTHONPATH PYTHONPATH="$site" "$PYTHON" - "$site" <<'PY'
import sys
import bcassim
assert bcassim.__file__.startswith(sys.argv[1]), bcassim.__file__
mesh = bcassim.mesh.make_box_mesh([1, 1, 1], 2, 2, 2)
print(f"bcassim {bcassim.__version__} from {bcassim.__file__}: {mesh}")
PY
