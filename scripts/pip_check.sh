#!/usr/bin/env bash
# The README's pip install, checked: a virtual environment with Debian's
# site packages (numpy, pybind11, setuptools), `pip install --no-build-isolation
# --no-index .` (offline), then `import simdbvh` from another folder and one
# query against a known answer.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$tmp/venv"
(cd "$root" && "$tmp/venv/bin/pip" install --quiet --no-build-isolation --no-index .)
rm -rf "$root/python/simdbvh.egg-info"
cd "$tmp"
"$tmp/venv/bin/python" - <<'PY'
import numpy as np
import simdbvh
assert "site-packages" in simdbvh.__file__, simdbvh.__file__
m = simdbvh.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
h = simdbvh.BVH(m).intersect([[0.25, 0.25, 2.0]], [[0, 0, -1]])
assert h["prim"][0] == 0 and h["t"][0] == 2.0, h
print("pip install ok:", simdbvh.__file__, simdbvh.isas())
PY
