#!/usr/bin/env bash
# The pip install of docs/python.md#building-and-installing, checked: a
# virtual environment with Debian's site packages (numpy, pybind11,
# setuptools), `pip install --no-build-isolation --no-index .` (offline), then
# `import simdbvh` from another folder and one query against a known answer.
# SIMDBVH_CMAKE_BUILD_DIR (CI sets it to build/release, .ci/run): setup.py then
# packages the simdbvh_python module of that already configured and built tree
# (`cmake --build <dir> --target simdbvh_python`, a no-op when up to date)
# instead of configuring a second tree and compiling every library again. CI's
# first stage has just compiled those same sources with the same flags (Release,
# no extra flags, the same interpreter: setup.py refuses a tree that differs);
# this check is about the packaging and the installation, and without the
# variable it built them all a second time (CI: about 190 s of this stage's
# 207 s). Unset (what users run), `pip install .` builds from scratch as before.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
tmp=$(mktemp -d); trap 'rm -rf "$tmp" "$root/python/simdbvh.egg-info"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$tmp/venv"
if [ -n "${SIMDBVH_CMAKE_BUILD_DIR:-}" ]; then
  export SIMDBVH_CMAKE_BUILD_DIR="$(cd "$root" && cd "$SIMDBVH_CMAKE_BUILD_DIR" && pwd)"
  echo "pip_check: packaging the module of $SIMDBVH_CMAKE_BUILD_DIR (SIMDBVH_CMAKE_BUILD_DIR)"
fi
(cd "$root" && "$tmp/venv/bin/pip" install --quiet --no-build-isolation --no-index .)
cd "$tmp"
"$tmp/venv/bin/python" - <<'PY'
import numpy as np
import simdbvh
assert "site-packages" in simdbvh.__file__, simdbvh.__file__
assert "site-packages" in simdbvh._simdbvh.__file__, simdbvh._simdbvh.__file__
m = simdbvh.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
h = simdbvh.BVH(m).intersect([[0.25, 0.25, 2.0]], [[0, 0, -1]])
assert h["prim"][0] == 0 and h["t"][0] == 2.0, h
print("pip install ok:", simdbvh.__file__, simdbvh.isas())
PY
